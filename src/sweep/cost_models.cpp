#include "sweep/cost_models.h"

#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "decide/cost_features.h"

namespace aovar::sweep {
using json = nlohmann::json;

std::string group_name(const Group& g) { return std::get<0>(g) + "/" + std::get<1>(g) + "/" + std::get<2>(g); }

// `!(x >= bound)` rather than `x < bound`: a NaN skill (a degenerate fold) is no skill.
Verdict judge_model(double cv_r2, double cv_spearman, double min_spearman) {
  std::string r2 = fmt::format("cross-validated R² {:.3g}", cv_r2), rho = fmt::format("held-out Spearman {:.3f}", cv_spearman);
  std::string fails;
  if (!(cv_r2 >= 0)) fails = r2 + " < 0";
  if (!(cv_spearman >= min_spearman)) fails += fmt::format("{}{} < {:.2f}", fails.empty() ? "" : ", ", rho, min_spearman);
  if (fails.empty()) return {true, fmt::format("{} >= 0, {} >= {:.2f}", r2, rho, min_spearman)};
  return {false, fails};
}

std::string not_predictive_label(const ModelFit& fit) {
  return fit.predictive ? std::string() : "not predictive (" + fit.reason + ")";
}

namespace {
void judge(ModelFit& fit, double min_spearman) {
  Verdict v = judge_model(fit.cv_r2, fit.cv_spearman, min_spearman);
  fit.predictive = v.predictive;
  fit.reason = v.reason;
  fit.verdict = (v.predictive ? "predictive: " : "not predictive: ") + v.reason;
}
}  // namespace

// The weighted-classes model: 13 features meet 30-40 rows, hence the ridge (lambda 0.3 on standardised
// features; chosen on the Sponza and atrium sweeps, bench/HISTORY.md, "bench/cost_model").
GroupModels fit_group_models(const std::vector<table::CostRow>& rows, double min_spearman) {
  GroupModels gm;
  for (const auto& row : rows) gm.groups[{row.scene, row.view, row.backend}].push_back(row);
  for (const auto& [g, rows] : gm.groups) {
    if (rows.size() < 8) continue;  // 5 folds need more than one row each, mostly
    // Three models, all reported: six compact features (static work per pixel and the pass structure),
    // thirteen instruction classes weighted by pixels, and, with 4 rows per parameter or more, every static
    // count plus the axis one-hots. Predictions use, of the predictive ones (judge_model), the one with the
    // best cross-validated Spearman.
    struct Spec {
      std::string name;
      decide::FeatureSpec features;
      double lambda;
    };
    // The target is the paired time (time_ms.paired: the ratio to the baseline timed in the same rounds,
    // times the baseline's min): rows measured in different batches drift apart by 5-10 % on this host,
    // which min-of-N alone does not remove. Spearman against the raw time_ms.min is reported next to it.
    std::vector<double> raw;
    for (const auto& r : rows) raw.push_back(r.time_ms.min);
    auto full = decide::axis_features(rows).then(decide::static_features());
    std::vector<Spec> specs = {{"compact static", decide::compact_features(), 1e-2}, {"weighted classes", decide::weighted_class_features(), 0.3}};
    if (rows.size() >= 4 * full.names.size()) specs.push_back({"static + axes", full, 1e-2});
    std::optional<ModelFit> best_refused;  // the not predictive one of best held-out Spearman
    for (const auto& sp : specs) {
      auto model = decide::fit_cost_model(rows, sp.features, sp.lambda);
      ModelFit fit;
      std::tie(fit.scene, fit.view, fit.backend) = g;
      fit.features = sp.name;
      fit.lambda = sp.lambda;
      fit.rows = model.n;
      fit.folds = model.cv.k;
      fit.cv_r2 = model.cv.r2;
      fit.cv_spearman = model.cv.spearman;
      fit.cv_spearman_min = decide::spearman(raw, model.cv.held_out);
      judge(fit, min_spearman);
      if (fit.predictive) {
        auto it = gm.best.find(g);
        if (it == gm.best.end() || model.cv.spearman > it->second.second.cv.spearman) gm.best[g] = {sp.name, model};
      } else if (!best_refused || fit.cv_spearman > best_refused->cv_spearman) {
        best_refused = fit;
      }
      gm.models.push_back(std::move(fit));
    }
    if (!gm.best.count(g) && best_refused) gm.unpredictable[g] = best_refused->reason;
  }
  for (auto& m : gm.models) {
    const Group g{m.scene, m.view, m.backend};
    auto it = gm.best.find(g);
    m.predicts = it != gm.best.end() && it->second.first == m.features;
    if (!m.predicts) continue;
    // The predicting model's held-out predictions, for the report's predicted-against-measured chart.
    const auto& rows = gm.groups.at(g);
    for (std::size_t i = 0; i < rows.size(); ++i)
      m.held_out.push_back({rows[i].variant, rows[i].time_ms.decision(), rows[i].time_ms.min,
                            it->second.second.cv.held_out[i]});
  }
  return gm;
}

const decide::CostModel* predicting_model(const GroupModels& gm, const Group& g) {
  if (auto it = gm.best.find(g); it != gm.best.end()) return &it->second.second;
  auto refused = gm.unpredictable.find(g);
  if (refused == gm.unpredictable.end()) return nullptr;
  throw std::runtime_error("sweep --predict: no predictive cost model for " + group_name(g) + " (best: " + refused->second +
                           "); measure these variants or lower --min-model-spearman");
}

}  // namespace aovar::sweep
