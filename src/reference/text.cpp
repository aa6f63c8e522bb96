#include "reference/text.h"

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::reference {

std::string to_text(const RunResult& r, const std::filesystem::path& out) {
  std::string s = fmt::format("{:<12} {:>9} {:>6} {:<10} {:>8} {:>9} {:>9} {:>7} {:>9} {:>8}\n", "view", "size",
                              "rays", "mode", "radius", "mean vis", "mean err", "bg %", "trace s", "Mrays/s");
  for (const auto& v : r.views)
    s += fmt::format("{:<12} {:>9} {:>6} {:<10} {:>8.4g} {:>9.4f} {:>9.4f} {:>7.1f} {:>9.2f} {:>8.2f}{}\n", v.view,
                     fmt::format("{}x{}", v.options.size.width, v.options.size.height), v.options.rays,
                     mode_name(v.options.mode), v.options.radius, v.stats.mean_visibility, v.stats.mean_std_error,
                     100.0 * v.stats.background_share, v.trace_s,
                     v.trace_s > 0 ? static_cast<double>(v.rays_traced) / v.trace_s / 1e6 : 0.0,
                     v.from_cache ? "  (cached)" : "");
  return s + fmt::format("# scene {} ({} triangles) in {:.1f} s -> {}\n", r.scene, r.triangles, r.wall_s,
                         util::display_path(out / "reference.json"));
}

}  // namespace aovar::reference
