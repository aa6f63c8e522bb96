#pragma once
// What a scene's profile dropped from a selection, as the run records it (cost_table.json meta.pruned[],
// measure.json, ship's choices): the counts, dropped per rule, and every dropped variant with its reason.
// profile/scene_prune.h decides it; the record lives with the table, whose header carries it.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aovar::table {

struct DroppedVariant {
  std::string variant;
  std::string rule;    // the profile's decision: "<axis> <value>" ("depth_format r16f")
  std::string reason;  // "<rule>: <evidence>", as `aovar list --scene S --pruned` prints it
  bool operator==(const DroppedVariant&) const = default;
};

struct PruningCounts {
  std::string scene;
  int selected = 0, kept = 0, dropped = 0;
  std::map<std::string, int> rules;     // rule -> variants it dropped
  std::vector<DroppedVariant> variants;  // the dropped ones
  bool operator==(const PruningCounts&) const = default;

  // "scene: N selected, K kept, D dropped (rule n, ...)": the report's and cost_table.md's line.
  std::string line() const;
  // "rule n, rule n": dropped per rule (empty when nothing was dropped).
  std::string rules_text() const;
};

nlohmann::json to_json(const PruningCounts& counts);
// The inverse; throws nlohmann::json errors naming what is missing or of the wrong type.
PruningCounts pruning_counts_from_json(const nlohmann::json& j);

}  // namespace aovar::table
