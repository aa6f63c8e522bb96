#pragma once
// What a sweep's own cost-model verdicts (meta.cost_models, meta.prune.scenes[].cost_models) say it must do:
// the tests that measure for real cannot choose whether a 9-row model of noisy 96x54 timings is predictive,
// so they read the verdicts and check the sweep did what those verdicts require.
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace aovar::test {

// "scene/view/backend" of every group in `cost_models` none of whose models is predictive.
inline std::set<std::string> unpredictable_groups(const nlohmann::json& cost_models) {
  std::set<std::string> fitted, predictive;
  for (const auto& m : cost_models) {
    const std::string g = m.at("scene").get<std::string>() + "/" + m.at("view").get<std::string>() + "/" +
                          m.at("backend").get<std::string>();
    fitted.insert(g);
    if (m.at("predictive").get<bool>()) predictive.insert(g);
  }
  std::set<std::string> out;
  for (const auto& g : fitted)
    if (!predictive.count(g)) out.insert(g);
  return out;
}

}  // namespace aovar::test
