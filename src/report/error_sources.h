#pragma once
// The reports' "Where the error comes from" per scene / view / backend: for the rows on the front, the error
// split by the screen-edge band and the interior, the near and far halves, too light and too dark
// (metrics/breakdown.h), and one reading of the worst parts generated from those numbers
// (metrics::breakdown_reading over their mean).
#include <string>
#include <vector>

#include "metrics/breakdown.h"
#include "report/grid.h"
#include "table/table.h"

namespace aovar::report {

// The rows of `rows` on the front that carry a breakdown, in the given order.
std::vector<const table::CostRow*> rows_with_breakdown(const std::vector<const table::CostRow*>& rows);

// One line per row: variant, RMSE, edge band (px), edge "error share / pixel share", edge and interior RMSE,
// near and far "error share (RMSE)", light and dark "error share (mean signed error)".
Grid error_sources_grid(const std::vector<const table::CostRow*>& rows);

// Each figure's mean over the breakdowns, leaving out NaNs (NaN where every one is NaN); {} for none.
metrics::ErrorBreakdown mean_breakdown(const std::vector<metrics::ErrorBreakdown>& breakdowns);

// The section for one group's rows (any order; the front is picked here): a heading, the grid and the
// reading. "" when no row on the front has a breakdown (tables measured before it, or without a reference).
std::string error_sources_markdown(const std::vector<const table::CostRow*>& rows);
std::string error_sources_html(const std::vector<const table::CostRow*>& rows);

}  // namespace aovar::report
