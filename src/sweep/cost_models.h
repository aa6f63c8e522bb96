#pragma once
// The sweep's cost models: per (scene, view, backend) with 8 rows or more, how well static features (and the
// axes) predict the measured time, cross-validated (decide/cost_model.h); the best predictive one predicts.
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "decide/cost_model.h"
#include "table/model_fit.h"

namespace aovar::sweep {

using Group = std::tuple<std::string, std::string, std::string>;  // scene, view, backend
std::string group_name(const Group& g);                            // "scene/view/backend"

// The least held-out Spearman ρ of a model that may predict (sweep --min-model-spearman). Below 0.7 the
// model orders about a quarter of the pairs of variants wrongly or more (for normal scores Kendall's τ is
// about 0.5 at ρ = 0.7, and (1 - τ)/2 of the pairs are discordant): too many to decide from which variant
// is faster, which is all that pruning and predicted rows are for.
inline constexpr double kMinModelSpearman = 0.7;

// Whether a model's cross-validated skill lets it predict: R² >= 0 (better than the mean time) and held-out
// ρ >= min_spearman. The reason names the numbers that fail ("held-out Spearman 0.590 < 0.70"), or, for a
// predictive model, both numbers that pass.
struct Verdict {
  bool predictive = false;
  std::string reason;
};
Verdict judge_model(double cv_r2, double cv_spearman, double min_spearman = kMinModelSpearman);

// One fitted model and its cross-validated skill (meta.cost_models[] in cost_table.json).
using table::ModelFit;

// "not predictive (<reason>)" for a model whose numbers are not a result, else "".
std::string not_predictive_label(const ModelFit& fit);

struct GroupModels {
  std::vector<ModelFit> models;  // every model fitted, with its skill
  std::map<Group, std::vector<table::CostRow>> groups;
  // The predicting model: among the predictive ones, the best held-out Spearman (name and model).
  std::map<Group, std::pair<std::string, decide::CostModel>> best;
  // Groups with fitted models, none predictive: the reason of the one with the best held-out Spearman.
  std::map<Group, std::string> unpredictable;
};

GroupModels fit_group_models(const std::vector<table::CostRow>& rows, double min_spearman = kMinModelSpearman);

// The model that predicts group `g`'s rows; nullptr when the group has too few rows for any model (it gets
// no predicted rows). Throws std::runtime_error with the one-line --predict refusal when its models are all
// not predictive: a prediction from them would be a guess presented as a time.
const decide::CostModel* predicting_model(const GroupModels& gm, const Group& g);

}  // namespace aovar::sweep
