// generate --from-table: the cost table's fronts (or select's picks) per GPU family and backend, as the
// variants to generate and the pick table to embed (decide/fronts.h does the choosing).
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "calibrate/file.h"
#include "cli/render_parts.h"
#include "compile/pick_table.h"
#include "decide/fronts.h"
#include "gpu/family_specs.h"
#include "render/backend.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::cli {
namespace {

bool is_backend(const std::string& name) {
  const auto names = render::backend_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

void check_target_names(const std::string& table, const std::vector<std::string>& targets) {
  for (const auto& name : targets)
    if (!is_backend(name) && !compile::is_amd_family(name) && !gpu::estimate_spec(name))
      throw std::runtime_error(fmt::format(
          "{}: --for '{}': not an AMD GPU family or a backend, nor a GL chip with an estimate (backends: {}; "
          "families, Mesa's names: {})",
          table, name, render::backend_list(), compile::amd_family_names()));
}

compile::PickFront pick_front(const decide::TargetFront& f) {
  compile::PickFront out{f.target, f.family, {}};
  for (const auto& p : f.points) out.points.push_back({p.variant, p.time_ms, p.rmse});
  return out;
}

std::string summary_line(const decide::TargetFront& f) {
  const auto& first = f.points.front();
  const auto& last = f.points.back();
  return fmt::format("{} {}: {} variant{} from {} ({:.3f} ms, rmse {:.5f}) to {} ({:.3f} ms, rmse {:.5f})\n",
                     f.family ? "family" : "backend", f.target, f.points.size(), f.points.size() == 1 ? "" : "s",
                     first.variant, first.time_ms, first.rmse, last.variant, last.time_ms, last.rmse);
}

// The fitted values the table's rows were scored with: meta.calibration's, once the file it names is found
// with the bytes that were scored. The recorded path is relative to where the sweep ran, so the file is
// looked for there, then beside the table (ship's OUT/calibration.json), then beside the manifest (the
// default calibration). A merged table names no file and carries the values alone. None recorded: the
// manifest's defaults.
// `found`: where the file is.
variants::CalibratedValues scored_parameters(const table::CostTable& t, const std::filesystem::path& table,
                                             const std::filesystem::path& manifest, std::filesystem::path& found) {
  if (!t.meta.calibration || !*t.meta.calibration) return {};
  const table::CalibrationRef& c = **t.meta.calibration;
  const std::string where = util::display_path(table);
  if (!c.file.empty()) {
    const std::filesystem::path name = std::filesystem::path(c.file).filename();
    // The first place that holds the scored bytes; else the first that holds a file of that name.
    std::filesystem::path file;
    std::optional<std::string> bytes;
    for (const std::filesystem::path& candidate : {std::filesystem::path(c.file), table.parent_path() / name,
                                                   manifest.parent_path() / name}) {
      auto read = util::read_file(candidate);
      if (!read || (bytes && util::hash_hex(*read) != c.hash)) continue;
      file = candidate;
      bytes = std::move(read);
      if (util::hash_hex(*bytes) == c.hash) break;
    }
    if (!bytes)
      throw std::runtime_error(fmt::format(
          "{}: error: its rows were scored with the calibration {}, which is not there, beside the table or beside "
          "the manifest; nothing was written (put the file back, or sweep again)",
          where, c.file));
    if (util::hash_hex(*bytes) != c.hash)
      throw std::runtime_error(fmt::format(
          "{}: error: the calibration {} changed after the table was scored (hash {}, recorded {}); nothing was "
          "written (restore it, or sweep again with it)",
          where, util::display_path(file), util::hash_hex(*bytes).substr(0, 12), c.hash.substr(0, 12)));
    found = file;
  }
  if (c.values.empty())
    throw std::runtime_error(fmt::format(
        "{}: error: the table records its calibration {} by hash alone (written before tables kept the fitted "
        "values); nothing was written (sweep again, or generate --variants ... --calibration FILE)",
        where, c.file.empty() ? "(merged)" : c.file));
  return c.values;
}

}  // namespace

variants::CalibratedValues calibration_values(const std::string& file, const variants::Manifest& manifest) {
  return calibrate::load_calibration(file, manifest);
}

TableChoice choose_from_table(const TableRequestArgs& a) {
  check_target_names(util::display_path(a.table), a.targets);
  const auto t = table::read_table(a.table);
  // Sweeps record the manifest's hash (older tables do not: generate then checks that the keys exist).
  if (t.meta.manifest_hash) {
    const auto text = util::read_file(a.manifest);
    if (text && *t.meta.manifest_hash != util::hash_hex(*text))
      throw std::runtime_error(fmt::format(
          "{}: error: this cost table was measured with another manifest: its meta.manifest_hash is not the hash of "
          "{}; nothing was written (sweep with this manifest, or generate with the table's)",
          util::display_path(a.table), util::display_path(a.manifest)));
  }
  decide::TableRequest request{util::display_path(a.table), a.targets, {}};
  request.pick.budget_ms = a.budget_ms;
  request.pick.max_error = a.max_error;
  request.pick.budget_of = a.budget_of;
  const auto keep = decide::keep_from_table(t, request, [](const std::string& name) { return !is_backend(name); });
  TableChoice choice{keep.keys, {}, {}, {}, {}};
  choice.parameters = scored_parameters(t, a.table, a.manifest, choice.calibration);
  for (const auto& f : keep.fronts) {
    choice.fronts.push_back(pick_front(f));
    choice.summary += summary_line(f);
  }
  return choice;
}

}  // namespace aovar::cli
