#include "decide/target_names.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "compile/pick_table.h"
#include "gpu/family_specs.h"
#include "render/backend.h"
#include "util/text.h"

namespace aovar::decide {
namespace {

// A name as the message shows it: one line, and not the whole of a hostile kilobyte.
std::string shown_name(const std::string& name) {
  std::string s = util::one_line(name);
  for (char& c : s)
    if (static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return s.size() > 64 ? s.substr(0, 64) + "..." : s;
}

[[noreturn]] void refuse_row(const std::string& table_name, std::size_t index, const table::CostRow& row,
                             const std::string& what) {
  throw std::runtime_error(fmt::format("{}: row {} ({}): {}; nothing was written (use a table aovar sweep wrote)",
                                       table_name, index, shown_name(row.key()), what));
}

}  // namespace

bool is_known_gpu(const std::string& name) {
  return compile::is_amd_family(name) || gpu::product_spec(name) != nullptr;
}

bool is_known_backend(const std::string& name) {
  const auto names = render::backend_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

void check_row_targets(const table::CostTable& table, const std::string& table_name) {
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const auto& row = table.rows[i];
    if (!is_known_backend(row.backend))
      refuse_row(table_name, i, row,
                 fmt::format("backend '{}' is not one aovar has (backends: {})", shown_name(row.backend),
                             render::backend_list()));
    for (const auto& [name, cost] : row.gpu)
      if (!is_known_gpu(name))
        refuse_row(table_name, i, row,
                   fmt::format("GPU '{}' in \"gpu\" is no GPU aovar knows (an AMD family of Mesa: {}; or a chip of "
                               "src/gpu/families.json)",
                               shown_name(name), compile::amd_family_names()));
  }
}

}  // namespace aovar::decide
