#pragma once
// Which of the race's survivors `aovar ship` times on the held-out views (issue 35). The held-out views
// serve one purpose: the selection. Their still errors are rendered first (one render, no timing), and a
// survivor is timed there only when the query could choose it whatever its time turns out to be:
//   --budget-of K: its held-out rmse is at most K's times (1 + the query's tolerance). K always fits its
//     own budget, so the choice has K's rmse or less; the tolerance keeps what `select` would still name as
//     worth considering (a faster one with nearly the choice's rmse);
//   --max-error E: its held-out rmse is at most E (nothing else fits). When none is, the lowest-error one
//     is timed, for the nearest that `select` reports;
//   --budget-ms X: every survivor (without its time, nothing rules a candidate out).
// Under a budget the timing is then staged in order of held-out error (holdout_settled): the choice is the
// most accurate survivor that fits, so once the most accurate ones timed hold a choice, every survivor less
// accurate than it (beyond the tolerance) is left untimed too.
// The rest keep their training-view rows (they stay on the training front); the reason each was not timed
// is recorded in the table's meta.
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "decide/select.h"
#include "table/table.h"

namespace aovar::ship {

struct HoldoutSkip {
  std::string variant;
  double rmse = 0;     // its worst held-out still error
  std::string reason;  // "held-out rmse 0.0712 > 0.0622, what the budget allows: cannot be chosen"
};

struct HoldoutPlan {
  std::vector<std::string> timed;     // sorted
  std::vector<std::string> by_error;  // `timed` in the order to time them: the budget's variant, then by rmse
  std::map<std::string, double> rmse;  // each survivor's worst held-out still rmse (where rendered)
  std::vector<HoldoutSkip> untimed;
  std::string rule;                   // the cut, in words ("rmse <= 0.0622 (alchemy-…'s 0.0610 + 2 %)")
};

// `stills`: the held-out still rows (error, no time) of the survivors; `survivors`: their keys. A survivor
// without a still error is timed (nothing is known against it); so is every survivor when the budget's own
// variant has no still error (the cut has no bound).
HoldoutPlan plan_holdout_timing(const table::CostTable& stills, const std::vector<std::string>& survivors,
                                const decide::SelectQuery& query);

// Staged timing under --budget-of or --budget-ms: `rows` holds the held-out rows of the first `n` of
// plan.by_error. When `select` makes a choice among them and every survivor after them has a held-out rmse
// above the choice's plus the query's tolerance, no later one can be chosen or named worth considering:
// returns that bound. nullopt: time more (never settled before all under --max-error, whose plan is its cut).
std::optional<double> holdout_settled(const table::CostTable& rows, const HoldoutPlan& plan, std::size_t n,
                                      const decide::SelectQuery& query);

// The held-out timing of `plan`: kHoldoutChunk more of plan.by_error at a time until holdout_settled (all at
// once under --max-error, whose plan is its cut). `time_first(keys)` times `keys` on the held-out views and
// returns their rows; each call's keys extend the last's (a resumable sweep reuses what it timed).
inline constexpr std::size_t kHoldoutChunk = 8;

struct HoldoutTiming {
  table::CostTable rows;            // the last call's: every timed survivor's held-out rows
  std::size_t timed = 0;            // the first `timed` of plan.by_error
  std::vector<HoldoutSkip> untimed;  // the rest, with why they could not be chosen
};

using TimeSurvivors = std::function<table::CostTable(const std::vector<std::string>& keys)>;
HoldoutTiming time_in_error_order(const HoldoutPlan& plan, const decide::SelectQuery& query,
                                  const TimeSurvivors& time_first);

}  // namespace aovar::ship
