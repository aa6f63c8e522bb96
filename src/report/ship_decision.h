#pragma once
// What `aovar ship` decided, read back from its table. meta.ship holds the question the held-out views
// answered (`query`), the line that builds the answer and every elimination; the decision is that question
// asked again of the table's held-out rows (decide::select), so the report and the terminal say the same.
#include <optional>
#include <string>
#include <vector>

#include "decide/select.h"
#include "table/table.h"

namespace aovar::report {

// One step of the search, with how many variants it left and how it decided.
struct FunnelStage {
  std::string stage;  // "space", "profile", "normals lean", a round's name, "held-out"
  int left = 0;
  int dropped = 0;
  std::string how;
};

// The choice against what it replaces: --budget-of's variant, else the baseline every round was timed against.
struct BaselineComparison {
  std::string variant;
  std::string time;                   // "0.842x [0.801, 0.880]" (the interval where the rounds give one)
  std::optional<double> rmse_delta;   // choice - baseline on the held-out views, where the baseline was scored there
  std::optional<table::CostRow> row;  // its held-out row, where the table has one (its images)
};

struct ShipDecision {
  std::string scene, target, backend;  // target: a GPU whose estimate decided; empty: the measured backend
  std::vector<std::string> holdout_views;
  decide::Selection selection;
  std::optional<table::CostRow> choice_row;  // the chosen variant on the first held-out view (its images)
  std::optional<BaselineComparison> baseline;
  std::string build_line;
  std::vector<FunnelStage> funnel;
};

// Every choice of a table `aovar ship` wrote, in --target order (one for a measured backend or one target),
// each asked again of the rows it was decided on (table::decided_rows); empty for a table ship did not
// write (a sweep, a merge) or one written before meta.ship held its query. Throws std::runtime_error naming
// meta.ship when it is malformed.
std::vector<ShipDecision> ship_decisions(const table::CostTable& table);

// "budget: 2.000 ms" / "budget: no slower than KEY" / "error target: RMSE at most 0.0500": what was asked.
std::string query_text(const decide::SelectQuery& q);

}  // namespace aovar::report
