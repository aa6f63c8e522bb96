#include "stress/text.h"

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::stress {

// --list-cases: name, scene and what each default case tests.
std::string cases_text(const std::vector<Case>& cases) {
  std::string s;
  for (const auto& c : cases) s += fmt::format("{:<20} {:<18} {}\n", c.name, c.scene, c.what);
  return s;
}

// Each failed variant with its failing checks and their reproducers, then the counts.
std::string to_text(const Result& r, const Options& o, const std::vector<Case>& cases) {
  std::string s;
  for (const auto& v : r.variants) {
    if (v.failures.empty()) continue;
    s += fmt::format("FAIL {}{}\n", v.variant, v.shipped ? " (shipped)" : "");
    for (std::size_t i : v.failures) {
      const auto& c = r.checks[i];
      s += fmt::format("  {} ({}): {}\n    reproduce: {}\n", c.case_name, c.backend, c.failure,
                       reproducer(o, c, cases));
    }
  }
  return s + fmt::format("# {} variants x {} cases x {} backends: {} checks ({} reused), {} variants failed, {} of them "
                         "shipped, in {:.1f} s{}\n",
                         r.variants.size(), cases.size(), o.backends.size(), r.checks.size(), r.reused, r.failed,
                         r.shipped_failed, r.wall_s,
                         o.out.empty() ? "" : " -> " + util::display_path(o.out / "stress.md") + " and stress.json");
}

}  // namespace aovar::stress
