#pragma once
// Which work a shard does: units of work (a variant with the variants that must run with it, or a stress
// case with its scaled copies) balanced over n shards by cost, not by count. A pure function of the units:
// every shard computes the same assignment from the same inputs, so no coordinator is needed.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aovar::shard {

struct Unit {
  std::string id;                    // unique, stable (a variant key, a case name)
  double cost = 1;                   // predicted cost (any unit; > 0)
  std::vector<std::string> members;  // what the unit covers (id included); empty: just id
};

struct Assignment {
  int count = 1;
  std::vector<int> shard_of_unit;     // parallel to the units given
  std::vector<double> loads;          // predicted cost per shard
  std::vector<int> units;             // units per shard
  double max_over_mean() const;       // 1 = perfectly balanced (1 when there is no load)
  nlohmann::json to_json() const;     // {"loads", "units", "max_over_mean"}
};

// Longest-processing-time first: units by cost (descending, then id), each to the least-loaded shard
// (ties: the lowest index). Throws std::runtime_error for count < 1, duplicate ids or a cost <= 0 / NaN.
Assignment assign(const std::vector<Unit>& units, int count);

// The members (or ids) of the units assigned to `index`.
std::vector<std::string> members_of(const std::vector<Unit>& units, const Assignment& a, int index);

// "plan: 14 units, predicted 26.1 % of the cost (ideal 25.0 %); max/mean over shards 1.04".
std::string balance_line(const Assignment& a, int index);

}  // namespace aovar::shard
