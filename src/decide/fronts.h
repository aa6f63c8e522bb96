#pragma once
// What a cost table keeps for the build (aovar generate --from-table): per target, a GPU family's estimate
// or a measured backend, the variants `aovar select` answers for some time budget, sorted by time. That is
// the Pareto front of time against worst-view error as select sees it (its candidates, its ties), so a
// lookup along it (the generated library's pick()) answers as select does for every budget.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "decide/select.h"
#include "table/table.h"

namespace aovar::decide {

struct FrontPoint {
  std::string variant;
  double time_ms = 0, rmse = 0;  // the candidate's: worst view, time on the target
};

struct TargetFront {
  std::string target;   // a GPU family ("navi21") or a measured backend
  bool family = false;  // a GPU family (time: its roofline estimate), else a measured backend
  std::vector<FrontPoint> points;  // by time, fastest first; error falls along it
};

// The targets a table has: each GPU family some row with an error has an estimate for (sorted), then each
// measured backend (sorted).
std::vector<std::string> families_in(const table::CostTable& table);
std::vector<std::string> backends_in(const table::CostTable& table);

// The select query for one target: a family decides by its estimate (SelectQuery::target), a backend by
// the time measured on it (SelectQuery::backend).
SelectQuery query_for(const std::string& target, bool family, SelectQuery request = {});

// The variants `select --budget-ms B` answers on `target` over every B, fastest first: select at the slowest
// candidate's time, then again just under each answer's time, until nothing fits. Empty when the table has
// no candidate for the target.
TargetFront budget_front(const table::CostTable& table, const std::string& target, bool family);

struct TableRequest {
  std::string table_name;            // for the one-line errors
  std::vector<std::string> targets;  // --for; empty: every family and backend in the table
  // --budget-ms / --budget-of / --max-error: keep only select's answer per target (none set: the fronts).
  SelectQuery pick;
};

struct TableKeep {
  std::vector<TargetFront> fronts;  // per target in request order (with a pick: its one answer)
  std::vector<std::string> keys;    // the union of their variants, sorted
};

// Throws std::runtime_error, one line naming the table: a requested target the table has no rows for (with
// the families and backends it has), or a pick that nothing satisfies on a target. `is_family` says which
// names are GPU families. Every row's backend and GPU names are checked first (decide/target_names.h).
TableKeep keep_from_table(const table::CostTable& table, const TableRequest& request,
                          const std::function<bool(const std::string&)>& is_family);

}  // namespace aovar::decide
