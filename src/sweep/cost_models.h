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

struct GroupModels {
  nlohmann::json models = nlohmann::json::array();  // meta.cost_models: every model fitted, with its skill
  std::map<Group, std::vector<table::CostRow>> groups;
  std::map<Group, std::pair<std::string, table::CostModel>> best;  // by held-out Spearman: name and model
};

GroupModels fit_group_models(const std::vector<table::CostRow>& rows);

}  // namespace aovar::sweep
