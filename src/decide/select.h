#pragma once
// `aovar select`: the variant to ship under a time budget or an error target, with the reason, the
// runners-up and the margin to the next one.
#include <optional>
#include <string>
#include <vector>

#include "decide/time_compare.h"
#include "table/table.h"
#include "util/intervals.h"

namespace aovar::decide {

struct SelectQuery {
  std::optional<double> budget_ms;   // lowest error with time_ms.decision() (paired, else min) <= budget
  // The budget as a variant's time (its worst view, in the query's scope): "no slower than what I ship now",
  // the same on any machine, where a figure in ms is one machine's. Instead of budget_ms.
  std::string budget_of;
  std::optional<double> max_error;   // cheapest with error.rmse <= max_error (time ties: the lowest rmse)
  std::string scene, view, backend;  // empty: all
  // An AMD family ("navi21"): time is the row's roofline estimate on it (gpu.<family>.est_ms, sweep --gpu)
  // instead of the time measured here; errors still come from the reference. Empty: the measured time.
  std::string target;
  // An alternative is worth a line when it gives up at most this share (0.02 = 2 %) of the criterion the
  // query did not fix: a variant faster beyond the noise for nearly the same error (budget), or one with
  // much less error for nearly the same time (max-error).
  double tolerance = 0.02;
};

// One variant on one backend, aggregated over the rows the query keeps: the worst view (max rmse,
// max decision time: paired, else min) unless a view was asked for.
struct Candidate {
  std::string variant, backend;
  double time_ms = 0, rmse = 0, ssim = 0;
  std::vector<std::string> views;  // the rows it aggregates
  std::string worst_error_view, worst_time_view;
  // The row that gives its worst (max) time, with its rounds: what its time is compared by (compare_time).
  table::CostRow time_row;
  util::Interval time_ci;       // 95 % interval of time_ms (time_row.time_ms.paired_ci; unknown with a target)
  double work_per_pixel = NAN;  // static cost (table::StaticCost::work_per_pixel) of that row; NaN when not analysed
};

// a's time against b's as the query sees it: compare_time on their time rows, or the point estimates on
// the target GPU (deterministic: no interval).
TimeComparison compare_candidates(const Candidate& a, const Candidate& b, const SelectQuery& q);

struct Selection {
  SelectQuery query;  // as answered: --budget-of resolved into budget_ms
  bool ok = false;
  // Why: the choice's ("lowest rmse of the 5 of 12 candidates within 2.000 ms (...)") or, when nothing
  // satisfies, what was asked and the nearest candidate.
  std::string reason;
  std::optional<Candidate> choice;
  std::vector<Candidate> runners_up;  // the next 3 in the order that made the choice
  // The candidates the query cannot tell from the choice on time (their time ratio's interval holds 1).
  // Max-error: every eligible candidate no other eligible one is faster than beyond the noise, but the
  // choice; the choice is the lowest rmse of them, then the lowest work per pixel, then point time, then key.
  // Budget: the eligible candidates tied with the choice (any rmse; the choice has the lowest).
  std::vector<Candidate> tied;
  util::Interval choice_ci;           // 95 % interval of the choice's time (unknown without rounds)
  bool may_exceed_budget = false;     // budget: choice_ci reaches beyond it
  std::optional<TimeComparison> margin;  // the runner-up's time against the choice's
  std::optional<Candidate> nearest;   // when nothing satisfies: fastest (budget) / lowest error (max-error)
  // Budget: the fastest candidate faster than the choice beyond the noise (at least 5 % when the comparison
  // has no interval: tables without rounds, a target's estimate) with rmse <= choice x (1 + tolerance).
  // Max-error: the lowest-error candidate with at least 5 % less rmse at time <= choice x (1 + tolerance).
  std::optional<Candidate> consider;
  std::string text;                   // what `aovar select` prints
};

// Candidates of the query (measured rows with an error only; with a target, those with an estimate on it),
// sorted by variant then backend.
std::vector<Candidate> candidates(const table::CostTable& table, const SelectQuery& q);

// Throws std::runtime_error when the query is malformed (neither or both criteria), no row matches the
// scene/view/backend filter, or no row has an estimate for the target (naming the families the table has).
Selection select(const table::CostTable& table, const SelectQuery& q);

// `aovar select --json`: the selection as one JSON document (schema_version, the query, ok, choice, reason,
// interval, ties, runners-up, margin, consider, nearest); candidates with their times, intervals and errors.
nlohmann::json to_json(const Selection& s);
// A query as JSON (in a selection, and in a ship table's meta.ship, where the report answers it again) and
// back. query_from_json throws std::runtime_error naming the field that is not what to_json writes.
nlohmann::json to_json(const SelectQuery& q);
SelectQuery query_from_json(const nlohmann::json& j);

}  // namespace aovar::decide
