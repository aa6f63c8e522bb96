// The Schwartz set of a "beats" relation (top_set.h): the closure that can hold it, then its strongly
// connected components (Tarjan 1972, iterative) and those no other component beats.
#include "decide/top_set.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace aovar::decide {
namespace {

constexpr std::size_t kUnset = std::numeric_limits<std::size_t>::max();

// Component of each node of a graph given as successor lists (Tarjan's algorithm with an explicit stack:
// the closure can be thousands of nodes deep).
std::vector<std::size_t> components(const std::vector<std::vector<std::size_t>>& succ) {
  const std::size_t n = succ.size();
  std::vector<std::size_t> index(n, kUnset), low(n, 0), comp(n, kUnset);
  std::vector<bool> on_stack(n, false);
  std::vector<std::size_t> stack;
  std::vector<std::pair<std::size_t, std::size_t>> calls;  // node, next successor to visit
  std::size_t next_index = 0, next_comp = 0;
  for (std::size_t root = 0; root < n; ++root) {
    if (index[root] != kUnset) continue;
    calls.push_back({root, 0});
    while (!calls.empty()) {
      auto& [v, i] = calls.back();
      if (i == 0 && index[v] == kUnset) {
        index[v] = low[v] = next_index++;
        stack.push_back(v);
        on_stack[v] = true;
      }
      if (i < succ[v].size()) {
        const std::size_t w = succ[v][i++];
        if (index[w] == kUnset) calls.push_back({w, 0});
        else if (on_stack[w]) low[v] = std::min(low[v], index[w]);
        continue;
      }
      if (low[v] == index[v]) {
        std::size_t w;
        do {
          w = stack.back();
          stack.pop_back();
          on_stack[w] = false;
          comp[w] = next_comp;
        } while (w != v);
        ++next_comp;
      }
      const std::size_t done = v;
      calls.pop_back();
      if (!calls.empty()) low[calls.back().first] = std::min(low[calls.back().first], low[done]);
    }
  }
  return comp;
}

}  // namespace

std::vector<std::size_t> schwartz_set(std::size_t n, std::size_t pivot,
                                      const std::function<bool(std::size_t, std::size_t)>& beats) {
  if (n == 0) return {};
  // Every source component holds the pivot or a member the pivot does not beat (a member it beats has the
  // pivot above it), so the closure of those under "is beaten by" holds the whole Schwartz set, and no
  // edge enters the closure from outside: its source components are the graph's.
  std::vector<std::size_t> local(n, kUnset), nodes;
  auto add = [&](std::size_t x) {
    if (local[x] != kUnset) return;
    local[x] = nodes.size();
    nodes.push_back(x);
  };
  for (std::size_t x = 0; x < n; ++x)
    if (x == pivot || !beats(pivot, x)) add(x);
  std::vector<std::pair<std::size_t, std::size_t>> edges;  // global (winner, loser), losers in the closure
  for (std::size_t k = 0; k < nodes.size(); ++k) {  // grows while it runs
    const std::size_t t = nodes[k];
    for (std::size_t y = 0; y < n; ++y)
      if (y != t && beats(y, t)) {
        edges.push_back({y, t});
        add(y);
      }
  }
  std::vector<std::vector<std::size_t>> succ(nodes.size());
  for (const auto& [w, l] : edges) succ[local[w]].push_back(local[l]);
  const std::vector<std::size_t> comp = components(succ);
  std::vector<bool> beaten_from_outside(nodes.size(), false);  // by component
  for (const auto& [w, l] : edges)
    if (comp[local[w]] != comp[local[l]]) beaten_from_outside[comp[local[l]]] = true;
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < nodes.size(); ++k)
    if (!beaten_from_outside[comp[k]]) out.push_back(nodes[k]);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace aovar::decide
