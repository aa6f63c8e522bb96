#pragma once
// A row's own 95 % intervals, from its rounds (table::Rounds): a property of the row, set where rows are
// read or made (measure.json, cost_table.json, tests). Comparing two rows is decide::compare_time.
#include "table/table.h"

namespace aovar::table {

// The baseline min that scales a row's paired time (paired = min x median ratio); 0 when unknown.
double paired_scale_ms(const CostRow& row);

// Per-row intervals from the rounds: rel_time_ci (sign test of the ratios) and time_ms.paired_ci (the same,
// times the baseline min that scales `paired`). Rows without rounds get unknown intervals.
void set_intervals(CostRow& row);

}  // namespace aovar::table
