#pragma once
// One fitted cost model and its cross-validated skill, as cost_table.json records it (meta.cost_models[]):
// sweep fits them (sweep/cost_models.h), the report draws them. The record lives with the row because the
// table's header carries it and the report, below sweep, reads it back.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aovar::table {

struct ModelFit {
  std::string scene, view, backend;
  std::string features;  // "compact static", "weighted classes", "static + axes"
  double lambda = 0;
  int rows = 0, folds = 0;
  double cv_r2 = 0, cv_spearman = 0;  // held-out, against the paired time (the target)
  double cv_spearman_min = 0;         // the same predictions against time_ms.min
  bool predictive = false;            // sweep::judge_model: its skill lets it predict at all
  std::string reason;                 // judge_model's reason
  std::string verdict;                // one line: "not predictive: <reason>" or "predictive: <reason>"
  bool predicts = false;              // the group's best predictive one: predicted rows and pruning use it
  struct HeldOut {
    std::string variant;
    double measured = 0, measured_min = 0, predicted = 0;
    bool operator==(const HeldOut&) const = default;
  };
  std::vector<HeldOut> held_out;      // the predicting model's held-out predictions (report chart)
  bool operator==(const ModelFit&) const = default;
};

// meta.cost_models: every fit, with "target": "time_ms.paired", "predictive", "verdict" and "reason".
nlohmann::json to_json(const std::vector<ModelFit>& fits);
// The inverse; a table older than "predictive" reads as predictive (its models were all used as such).
// Throws nlohmann::json errors on a malformed entry.
std::vector<ModelFit> model_fits_from_json(const nlohmann::json& fits);

}  // namespace aovar::table
