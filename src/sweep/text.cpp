#include "sweep/text.h"

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::sweep {
namespace fs = std::filesystem;

namespace {
// A not predictive model's numbers are its reason, not a result: no "R2 -51.7" presented as skill.
std::string model_line(const ModelFit& m) {
  if (!m.predictive)
    return fmt::format("# cost model {} {} {}: {} rows, {} features: {}\n", m.scene, m.view, m.backend, m.rows,
                       m.features, not_predictive_label(m));
  return fmt::format("# cost model {} {} {}: {} rows, cross-validated R2 {:.3f}, Spearman {:.3f} (against time_ms.min "
                     "{:.3f}; {} features){}\n",
                     m.scene, m.view, m.backend, m.rows, m.cv_r2, m.cv_spearman, m.cv_spearman_min, m.features,
                     m.predicts ? ", predicts" : "");
}
}  // namespace

std::string notes_text(const SweepResult& r, const SweepOptions& o, const fs::path& cal_file) {
  std::string s;
  for (const auto& m : r.cost_models)
    s += model_line(m);
  if (o.prune_dominated)
    s += fmt::format("# prune: {} variants skipped as predicted dominated; {} more measured anyway as a check, "
                     "{} of them on the Pareto front (cost_table.json meta.prune)\n",
                     r.variants_skipped, r.variants_checked, r.checked_on_front);
  if (o.prune_by_profile)
    s += fmt::format("# scene profiles: {} ({} reused) in {:.2f} s; each dropped variant with its reason: "
                     "cost_table.json meta.pruned (--no-prune measures them)\n",
                     o.scenes.size(), r.profiles_reused, r.profile_s);
  s += fmt::format("# timing: {}; reached: {}\n", measure::reps_words(o.measure), r.reps.text());
  s += fmt::format("# {} rows ({} measured, {} reused, {} predicted) in {:.1f} s{} -> {}\n", r.table.rows.size(),
                   r.rows_measured, r.rows_reused, r.rows_predicted, r.wall_s,
                   cal_file.empty() ? "" : ", calibrated by " + util::display_path(cal_file),
                   util::display_path(o.out / "cost_table.json"));
  return s + "# report: " + util::display_path(o.out / "report.html") + " (and report.md)\n";
}

}  // namespace aovar::sweep
