#include "decide/fronts.h"
#include "decide/target_names.h"
#include "table/on_views.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>

namespace aovar::decide {

namespace {

bool candidate_row(const table::CostRow& r) { return r.error && !r.predicted && r.same_code_as.empty(); }

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

}  // namespace

std::vector<std::string> families_in(const table::CostTable& table) {
  std::set<std::string> f;
  for (const auto& r : table.rows)
    if (candidate_row(r))
      for (const auto& [family, cost] : r.gpu)
        if (std::isfinite(cost.est_ms)) f.insert(family);
  return {f.begin(), f.end()};
}

std::vector<std::string> backends_in(const table::CostTable& table) {
  std::set<std::string> b;
  for (const auto& r : table.rows)
    if (candidate_row(r)) b.insert(r.backend);
  return {b.begin(), b.end()};
}

SelectQuery query_for(const std::string& target, bool family, SelectQuery request) {
  (family ? request.target : request.backend) = target;
  return request;
}

TargetFront budget_front(const table::CostTable& table, const std::string& target, bool family) {
  TargetFront front{target, family, {}};
  SelectQuery q = query_for(target, family);
  q.max_error = 1e300;  // any criterion: candidates() only reads the filters
  std::vector<double> times;
  for (const auto& c : candidates(table, q)) times.push_back(c.time_ms);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  q.max_error.reset();
  // select's answer changes only where the budget passes a candidate's time: asking just under each answer
  // finds the next one, so this asks once per front point (and once more).
  for (auto next = times.end(); next != times.begin();) {
    q.budget_ms = *std::prev(next);
    const Selection s = select(table, q);
    if (!s.ok) break;
    front.points.push_back({s.choice->variant, s.choice->time_ms, s.choice->rmse});
    next = std::lower_bound(times.begin(), times.end(), s.choice->time_ms);
  }
  std::reverse(front.points.begin(), front.points.end());
  return front;
}

namespace {

// The targets asked for, each checked against the table: one line naming it and what the table has.
std::vector<std::pair<std::string, bool>> checked_targets(const table::CostTable& table, const TableRequest& r,
                                                          const std::function<bool(const std::string&)>& is_family) {
  const auto families = families_in(table), backends = backends_in(table);
  std::vector<std::pair<std::string, bool>> out;
  if (r.targets.empty()) {
    for (const auto& f : families) out.emplace_back(f, true);
    for (const auto& b : backends) out.emplace_back(b, false);
  }
  for (const auto& name : r.targets) {
    const bool family = is_family(name);
    const auto& have = family ? families : backends;
    if (std::find(have.begin(), have.end(), name) == have.end())
      throw std::runtime_error(fmt::format(
          "{}: no rows with an error for {} '{}' (the table has GPU estimates for: {}; measured backends: {}); "
          "{} or drop it from --for / FOR",
          r.table_name, family ? "GPU family" : "backend", name, joined(families), joined(backends),
          family ? "run aovar sweep --gpu " + name : "run aovar sweep --backends " + name));
    out.emplace_back(name, family);
  }
  if (out.empty())
    throw std::runtime_error(r.table_name + ": no measured row with an error (sweep with a reference) to choose from");
  return out;
}

bool has_pick(const SelectQuery& q) { return q.budget_ms || q.max_error || !q.budget_of.empty(); }

}  // namespace

TableKeep keep_from_table(const table::CostTable& table, const TableRequest& request,
                          const std::function<bool(const std::string&)>& is_family) {
  check_row_targets(table, request.table_name);  // before a name is chosen by, or reaches generated code
  TableKeep keep;
  std::set<std::string> keys;
  for (const auto& [target, family] : checked_targets(table, request, is_family)) {
    TargetFront front{target, family, {}};
    // A ship table is decided on its held-out views, among what survived on the target: the build keeps
    // what ship chose.
    const table::CostTable decided = table::decided_rows(table, target);
    if (has_pick(request.pick)) {
      const Selection s = select(decided, query_for(target, family, request.pick));
      if (!s.ok) throw std::runtime_error(fmt::format("{}: on {}: {}", request.table_name, target, s.reason));
      front.points.push_back({s.choice->variant, s.choice->time_ms, s.choice->rmse});
    } else {
      front = budget_front(decided, target, family);
    }
    for (const auto& p : front.points) keys.insert(p.variant);
    keep.fronts.push_back(std::move(front));
  }
  keep.keys.assign(keys.begin(), keys.end());
  return keep;
}

}  // namespace aovar::decide
