// meta.cost_models[] read and written.
#include "table/model_fit.h"

namespace aovar::table {

using json = nlohmann::json;

json to_json(const std::vector<ModelFit>& fits) {
  json out = json::array();
  for (const auto& m : fits) {
    json j = {{"scene", m.scene},   {"view", m.view},         {"backend", m.backend},
              {"rows", m.rows},     {"cv_r2", m.cv_r2},       {"cv_spearman", m.cv_spearman},
              {"cv_spearman_min", m.cv_spearman_min},         {"target", "time_ms.paired"},
              {"folds", m.folds},   {"features", m.features}, {"lambda", m.lambda},
              {"predictive", m.predictive}, {"verdict", m.verdict}, {"reason", m.reason},
              {"predicts", m.predicts}};
    if (m.predicts) {
      json held = json::array();
      for (const auto& h : m.held_out)
        held.push_back({{"variant", h.variant}, {"measured", h.measured}, {"measured_min", h.measured_min},
                        {"predicted", h.predicted}});
      j["held_out"] = held;
    }
    out.push_back(std::move(j));
  }
  return out;
}

std::vector<ModelFit> model_fits_from_json(const json& fits) {
  std::vector<ModelFit> out;
  for (const auto& j : fits) {
    ModelFit m;
    m.scene = j.at("scene").get<std::string>();
    m.view = j.at("view").get<std::string>();
    m.backend = j.at("backend").get<std::string>();
    m.features = j.value("features", std::string());
    m.lambda = j.value("lambda", 0.0);
    m.rows = j.value("rows", 0);
    m.folds = j.value("folds", 0);
    m.cv_r2 = j.value("cv_r2", 0.0);
    m.cv_spearman = j.value("cv_spearman", 0.0);
    m.cv_spearman_min = j.value("cv_spearman_min", 0.0);
    m.predictive = j.value("predictive", true);
    m.reason = j.value("reason", std::string());
    m.verdict = j.value("verdict", std::string());
    m.predicts = j.value("predicts", false);
    for (const auto& h : j.value("held_out", json::array()))
      m.held_out.push_back({h.at("variant").get<std::string>(), h.value("measured", 0.0), h.value("measured_min", 0.0),
                            h.value("predicted", 0.0)});
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace aovar::table
