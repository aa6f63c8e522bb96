#include "util/output_apart.h"

#include <stdexcept>
#include <string>

#include "util/fs.h"

namespace aovar::util {
namespace {

std::filesystem::path resolved(const std::filesystem::path& p) {
  std::error_code ec;
  auto r = std::filesystem::weakly_canonical(std::filesystem::absolute(p), ec);
  return ec ? std::filesystem::absolute(p).lexically_normal() : r;
}

// Whether `inner` is `outer` or lies below it (component-wise, not as text: /a/bc is not below /a/b).
bool within(const std::filesystem::path& inner, const std::filesystem::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

}  // namespace

void check_output_apart_from_inputs(const std::filesystem::path& out, const std::vector<std::filesystem::path>& inputs,
                                    std::string_view what) {
  const auto o = resolved(out);
  for (const auto& in : inputs) {
    const auto i = resolved(in);
    const char* how = o == i ? "is" : within(o, i) ? "lies inside" : within(i, o) ? "holds" : nullptr;
    if (how)
      throw std::runtime_error(std::string(what) + ": the output " + display_path(out) + " " + how + " the input " +
                               display_path(in) + ": a join never writes into its inputs; choose another output");
  }
}

}  // namespace aovar::util
