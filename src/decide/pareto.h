#pragma once
// The Pareto front of time and error and the worst view: which rows are worth shipping, per group.
#include <vector>

#include "table/table.h"

namespace aovar::decide {

// Pareto front of (time, error.rmse), both minimised, per (scene, view, backend): sets `pareto` on every
// row (false for rows without an error and for same_code_as rows). Time is compared with its interval
// (compare_time, decide/time_compare.h): a row is dominated by another whose error is no higher and whose
// time is lower or tied (the interval of the difference holds 0), with lower error or a time lower beyond
// the noise. Rows tied in both are all on the front (deterministic).
void mark_pareto(std::vector<table::CostRow>& rows);
inline void mark_pareto(table::CostTable& t) { mark_pareto(t.rows); }

// The worst view of each scene: per (scene, variant, backend, size, threads) one row with view
// "worst(<views>)", error = the row with max rmse's error, time_ms = the max of each statistic over the
// views, but paired, its interval, the rounds and gbuffer_ms, which are the slowest view's; then Pareto-marked per
// (scene, backend). Rows without an error are left out.
std::vector<table::CostRow> worst_view(const std::vector<table::CostRow>& rows);

}  // namespace aovar::decide
