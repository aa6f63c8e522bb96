// A selection's pruning counts, as text and as JSON.
#include "table/pruning_counts.h"

#include <fmt/format.h>

namespace aovar::table {

using json = nlohmann::json;

std::string PruningCounts::rules_text() const {
  std::string text;
  for (const auto& [rule, n] : rules) text += fmt::format("{}{} {}", text.empty() ? "" : ", ", rule, n);
  return text;
}

std::string PruningCounts::line() const {
  const std::string text = rules_text();
  return fmt::format("{}: {} selected, {} kept, {} dropped{}", scene, selected, kept, dropped,
                     text.empty() ? "" : " (" + text + ")");
}

json to_json(const PruningCounts& c) {
  json variants = json::array();
  for (const auto& d : c.variants) variants.push_back({{"variant", d.variant}, {"rule", d.rule}, {"reason", d.reason}});
  return {{"scene", c.scene}, {"selected", c.selected}, {"kept", c.kept}, {"dropped", c.dropped},
          {"rules", c.rules}, {"variants", variants}};
}

PruningCounts pruning_counts_from_json(const json& j) {
  PruningCounts c;
  c.scene = j.at("scene").get<std::string>();
  c.selected = j.at("selected").get<int>();
  c.kept = j.at("kept").get<int>();
  c.dropped = j.at("dropped").get<int>();
  c.rules = j.value("rules", std::map<std::string, int>());
  for (const auto& d : j.value("variants", json::array()))
    c.variants.push_back({d.at("variant").get<std::string>(), d.at("rule").get<std::string>(),
                          d.at("reason").get<std::string>()});
  return c;
}

}  // namespace aovar::table
