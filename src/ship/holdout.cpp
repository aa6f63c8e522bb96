#include "ship/holdout.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include <fmt/format.h>

namespace aovar::ship {

namespace {

// Each variant's worst (max) still rmse over the held-out rows.
std::map<std::string, double> worst_rmse(const table::CostTable& stills) {
  std::map<std::string, double> out;
  for (const auto& r : stills.rows) {
    if (!r.error || std::isnan(r.error->rmse)) continue;
    auto [it, fresh] = out.try_emplace(r.variant, r.error->rmse);
    if (!fresh) it->second = std::max(it->second, r.error->rmse);
  }
  return out;
}

// The highest held-out rmse the query could still choose, with the rule in words; nullopt: no bound.
std::optional<std::pair<double, std::string>> bound_of(const std::map<std::string, double>& rmse,
                                                       const std::vector<std::string>& survivors,
                                                       const decide::SelectQuery& q) {
  if (!q.budget_of.empty()) {
    auto it = rmse.find(q.budget_of);
    if (it == rmse.end()) return std::nullopt;
    const double bound = it->second * (1 + q.tolerance);
    return std::pair{bound, fmt::format("rmse <= {:.5f} ({}'s {:.5f} + {:g} %, select's tolerance)", bound, q.budget_of,
                                        it->second, 100 * q.tolerance)};
  }
  if (q.max_error) {
    double lowest = INFINITY;
    for (const auto& k : survivors)
      if (auto it = rmse.find(k); it != rmse.end()) lowest = std::min(lowest, it->second);
    if (lowest > *q.max_error)  // nothing fits: the nearest (lowest error) is what select reports
      return std::pair{lowest, fmt::format("none within --max-error {:g}: the lowest rmse {:.5f} only, the nearest", *q.max_error, lowest)};
    return std::pair{*q.max_error, fmt::format("rmse <= {:g} (--max-error)", *q.max_error)};
  }
  return std::nullopt;  // --budget-ms: a candidate's time decides, and it is not known yet
}

}  // namespace

HoldoutPlan plan_holdout_timing(const table::CostTable& stills, const std::vector<std::string>& survivors,
                                const decide::SelectQuery& q) {
  const std::map<std::string, double> rmse = worst_rmse(stills);
  const auto bound = bound_of(rmse, survivors, q);
  HoldoutPlan plan;
  plan.rule = bound ? bound->second : "every survivor (the query's bound needs times)";
  for (const auto& k : survivors) {
    auto it = rmse.find(k);
    if (!bound || it == rmse.end() || it->second <= bound->first || k == q.budget_of) {
      plan.timed.push_back(k);
      continue;
    }
    plan.untimed.push_back({k, it->second,
                            fmt::format("held-out rmse {:.5f} > {:.5f}: the query cannot choose it", it->second, bound->first)});
  }
  std::sort(plan.timed.begin(), plan.timed.end());
  plan.rmse = rmse;
  plan.by_error = plan.timed;
  const auto order = [&](const std::string& k) {  // the budget's variant first (every selection needs it), unrendered last
    auto it = rmse.find(k);
    return std::tuple(k != q.budget_of, it == rmse.end() ? INFINITY : it->second, k);
  };
  std::sort(plan.by_error.begin(), plan.by_error.end(),
            [&](const std::string& a, const std::string& b) { return order(a) < order(b); });
  return plan;
}

std::optional<double> holdout_settled(const table::CostTable& rows, const HoldoutPlan& plan, std::size_t n,
                                      const decide::SelectQuery& q) {
  if (n >= plan.by_error.size()) return INFINITY;  // everything is timed
  if (q.max_error || rows.rows.empty()) return std::nullopt;
  if (!q.budget_of.empty()) {  // the budget's row resolves the budget: until it is timed there is nothing to decide by
    const auto timed = decide::candidates(rows, q);
    if (std::none_of(timed.begin(), timed.end(), [&](const decide::Candidate& c) { return c.variant == q.budget_of; }))
      return std::nullopt;
  }
  const decide::Selection s = decide::select(rows, q);
  if (!s.choice) return std::nullopt;
  const double bound = s.choice->rmse * (1 + q.tolerance);
  for (std::size_t i = n; i < plan.by_error.size(); ++i) {
    auto it = plan.rmse.find(plan.by_error[i]);
    if (it == plan.rmse.end() || it->second <= bound) return std::nullopt;
  }
  return bound;
}

HoldoutTiming time_in_error_order(const HoldoutPlan& plan, const decide::SelectQuery& q, const TimeSurvivors& time_first) {
  HoldoutTiming out;
  if (plan.by_error.empty()) return out;  // nothing to time (and no keys must never reach a sweep: none selects all)
  std::optional<double> settled;
  while (!settled) {
    out.timed = q.max_error ? plan.by_error.size() : std::min(plan.by_error.size(), out.timed + kHoldoutChunk);
    out.rows = time_first({plan.by_error.begin(), plan.by_error.begin() + std::ptrdiff_t(out.timed)});
    settled = holdout_settled(out.rows, plan, out.timed, q);
  }
  for (std::size_t i = out.timed; i < plan.by_error.size(); ++i) {
    const std::string& k = plan.by_error[i];
    const double rmse = plan.rmse.at(k);
    out.untimed.push_back({k, rmse, fmt::format("held-out rmse {:.5f} > {:.5f}, the choice's among the more accurate ones "
                                                "timed + {:g} %: not chosen, whatever its time",
                                                rmse, *settled / (1 + q.tolerance), 100 * q.tolerance)});
  }
  return out;
}

}  // namespace aovar::ship
