#pragma once
// The sweep's cost models: per (scene, view, backend) with 8 rows or more, how well static features (and the
// axes) predict the measured time, cross-validated (table/cost_model.h); the best one predicts.
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "table/cost_model.h"

namespace aovar::sweep {

using Group = std::tuple<std::string, std::string, std::string>;  // scene, view, backend

// One fitted model and its cross-validated skill (meta.cost_models[] in cost_table.json).
struct ModelFit {
  std::string scene, view, backend;
  std::string features;  // "compact static", "weighted classes", "static + axes"
  double lambda = 0;
  int rows = 0, folds = 0;
  double cv_r2 = 0, cv_spearman = 0;  // held-out, against the paired time (the target)
  double cv_spearman_min = 0;         // the same predictions against time_ms.min
  bool predicts = false;              // the group's best: predicted rows and pruning use it
  struct HeldOut {
    std::string variant;
    double measured = 0, measured_min = 0, predicted = 0;
  };
  std::vector<HeldOut> held_out;      // the predicting model's held-out predictions (report chart)
};

// meta.cost_models: every fit, with "target": "time_ms.paired".
nlohmann::json to_json(const std::vector<ModelFit>& fits);

struct GroupModels {
  std::vector<ModelFit> models;  // every model fitted, with its skill
  std::map<Group, std::vector<table::CostRow>> groups;
  std::map<Group, std::pair<std::string, table::CostModel>> best;  // by held-out Spearman: name and model
};

GroupModels fit_group_models(const std::vector<table::CostRow>& rows);

}  // namespace aovar::sweep
