// Cost-balanced, deterministic shard assignment (LPT: Graham 1969's longest-processing-time rule, within 4/3
// of the optimal makespan; written here because it is ten lines and no Debian library offers it).
#include "shard/assign.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

namespace aovar::shard {

double Assignment::max_over_mean() const {
  double total = std::accumulate(loads.begin(), loads.end(), 0.0);
  if (loads.empty() || total <= 0) return 1;
  return *std::max_element(loads.begin(), loads.end()) / (total / static_cast<double>(loads.size()));
}

nlohmann::json Assignment::to_json() const {
  return {{"loads", loads}, {"units", units}, {"max_over_mean", max_over_mean()}};
}

Assignment assign(const std::vector<Unit>& units, int count) {
  if (count < 1) throw std::runtime_error(fmt::format("shard count {} < 1", count));
  // Before anything per shard is allocated: a shard with no unit has nothing to do, and a count nobody
  // could mean (1/1000000000) would allocate and write an entry per shard.
  if (static_cast<std::size_t>(count) > units.size())
    throw std::runtime_error(fmt::format("--shard: {} shards for {} unit{} of work; use at most {} shards", count,
                                         units.size(), units.size() == 1 ? "" : "s", units.size()));
  std::set<std::string> ids;
  for (const auto& u : units) {
    if (!ids.insert(u.id).second) throw std::runtime_error("shard assignment: unit " + u.id + " appears twice");
    if (!(u.cost > 0) || !std::isfinite(u.cost))
      throw std::runtime_error(fmt::format("shard assignment: unit {} has cost {} (must be > 0)", u.id, u.cost));
  }
  std::vector<std::size_t> order(units.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (units[a].cost != units[b].cost) return units[a].cost > units[b].cost;
    return units[a].id < units[b].id;
  });
  Assignment a;
  a.count = count;
  a.shard_of_unit.assign(units.size(), 0);
  a.loads.assign(count, 0.0);
  a.units.assign(count, 0);
  for (std::size_t i : order) {
    int best = static_cast<int>(std::min_element(a.loads.begin(), a.loads.end()) - a.loads.begin());
    a.shard_of_unit[i] = best;
    a.loads[best] += units[i].cost;
    ++a.units[best];
  }
  return a;
}

std::vector<std::string> members_of(const std::vector<Unit>& units, const Assignment& a, int index) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < units.size(); ++i) {
    if (a.shard_of_unit.at(i) != index) continue;
    if (units[i].members.empty()) out.push_back(units[i].id);
    else out.insert(out.end(), units[i].members.begin(), units[i].members.end());
  }
  return out;
}

std::string balance_line(const Assignment& a, int index) {
  double total = std::accumulate(a.loads.begin(), a.loads.end(), 0.0);
  double share = total > 0 ? 100 * a.loads.at(index) / total : 0;
  return fmt::format("{} units, {:.1f} % of the predicted cost (ideal {:.1f} %); max/mean over the {} shards {:.2f}",
                     a.units.at(index), share, 100.0 / a.count, a.count, a.max_over_mean());
}

}  // namespace aovar::shard
