#include "measure/text.h"

#include <algorithm>

#include <fmt/format.h>

#include "metrics/breakdown_text.h"
#include "util/fs.h"

namespace aovar::measure {
namespace fs = std::filesystem;

std::string to_text(const MeasureResult& r) {
  bool truth = std::any_of(r.rows.begin(), r.rows.end(), [](const auto& row) { return row.error.has_value(); });
  std::string s = fmt::format("{:<46} {:<9} {:<10} {:>8} {:>8} {:>8} {:>20} {}  {}\n", "variant", "backend", "view",
                              "min ms", "median", "p90", "rel [95 %]", truth ? "  rmse    ssim" : "", "passes (min ms)");
  for (const auto& row : r.rows) {
    std::string passes;
    for (const auto& [name, st] : row.passes) passes += fmt::format("{} {:.2f}  ", name, st.min);
    std::string error = !truth ? "" : row.error ? fmt::format("{:>6.4f} {:>7.4f}", row.error->rmse, row.error->ssim)
                                                : fmt::format("{:>14}", "-");
    // The median ratio to the baseline in the same rounds, with its 95 % interval (docs/confidence.md).
    const auto& ci = row.rel_time_ci;
    std::string rel = ci.known() ? fmt::format("{:.3f} [{:.3f}, {:.3f}]", row.rel_time_median, ci.lo, ci.hi)
                                 : fmt::format("{:.3f}", row.rel_time_median);
    s += fmt::format("{:<46} {:<9} {:<10} {:>8.2f} {:>8.2f} {:>8.2f} {:>20} {}  {}{}\n", row.variant, row.backend,
                     row.view, row.time_ms.min, row.time_ms.median, row.time_ms.p90, rel, error, passes,
                     row.is_baseline ? "(baseline)" : row.reused ? "(reused)" : "");
  }
  return s + where_text(r);
}

// Per row with a reference: where its error comes from, the figures and their reading (metrics/breakdown_text.h).
std::string where_text(const MeasureResult& r) {
  std::string s;
  for (const auto& row : r.rows)
    if (row.error && row.error->breakdown)
      s += fmt::format("  {} {} {}: {}\n    {}\n", row.variant, row.backend, row.view,
                       metrics::breakdown_summary(*row.error->breakdown), metrics::breakdown_reading(*row.error->breakdown));
  return s.empty() ? s : "where the error comes from:\n" + s;
}

std::string notes_text(const MeasureResult& r, const MeasureOptions& o, const fs::path& cal_file) {
  std::string s;
  for (const auto& d : r.devices)
    s += fmt::format("# {}: {}, {}, {} threads{}\n", d.backend, d.device, d.api_version, d.threads,
                     d.timing.empty() || d.timing == "timestamp queries" ? "" : "; timing: " + d.timing);
  const std::string json = o.out.empty() ? "" : util::display_path(o.out / "measure.json");
  s += fmt::format("# scene {} ({} triangles), radius {:.3g}, {} at {}x{}, {} after {} warm-up; {}; "
                   "{} rows ({} reused) in {:.1f} s{}\n",
                   r.scene, r.triangles, r.radius, o.baseline, o.size.width, o.size.height, reps_words(o), o.timing.warmup,
                   r.counts, r.rows.size(), r.reused, r.wall_s, o.out.empty() ? "" : " -> " + json);
  s += "# timing reached: " + reps_reached(r).text() + "\n";
  if (r.pruning)
    s += fmt::format("# pruned by the scene's profile: {} ({}){}\n", r.pruning->summary(o.globs),
                     r.pruning->reused ? fmt::format("profile reused in {:.2f} s", r.pruning->seconds)
                                       : fmt::format("profiled in {:.1f} s", r.pruning->seconds),
                     o.out.empty() ? std::string()
                                   : "; each with its reason in " + json + " \"pruned\" (--no-prune measures them)");
  if (!o.calibration.values.empty())
    s += "# calibrated parameters: " + util::display_path(cal_file) + " (--no-calibration: the manifest's defaults)\n";
  for (const auto& sheet : r.contact_sheets) s += "# contact sheet: " + util::display_path(o.out / sheet) + "\n";
  return s;
}

}  // namespace aovar::measure
