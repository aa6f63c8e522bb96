#pragma once
// A measured cost-table row as measure writes it, for the table tests: builtin:atrium / overview on lavapipe
// at 64x36 with 2 threads, its per-round ratios to the baseline, the paired time (baseline min x median
// ratio), min / median / p90 from the ratios and the intervals set_intervals derives from them.
#include <algorithm>
#include <string>
#include <vector>

#include "table/table.h"
#include "table/time_compare.h"

namespace aovar::test {

inline constexpr const char* kAtriumScale = "base@builtin:atrium/overview/lavapipe/llvmpipe/64x36/2";

// A row without rounds (decided by its point time ms), with an error against the reference.
inline table::CostRow point_row(const std::string& variant, double ms, double rmse) {
  table::CostRow r;
  r.variant = variant;
  r.scene = "builtin:atrium";
  r.view = "overview";
  r.backend = "lavapipe";
  r.size = "64x36";
  r.threads = 2;
  r.time_ms.min = r.time_ms.median = r.time_ms.p90 = ms;
  r.time_ms.n = 10;
  metrics::ErrorStats e;
  e.rmse = rmse;
  e.ssim = 1 - rmse;
  r.error = e;
  return r;
}

inline table::CostRow timed_row(const std::string& variant, std::vector<double> ratios, double rmse,
                                const std::string& batch = "b1", double baseline_ms = 1) {
  table::CostRow r = point_row(variant, 0, rmse);
  std::vector<double> sorted = ratios;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  r.rel_time_median = n % 2 ? sorted[n / 2] : (sorted[n / 2 - 1] + sorted[n / 2]) / 2;
  r.rel_time = sorted.front();
  r.time_ms = {baseline_ms * sorted.front(), baseline_ms * r.rel_time_median, baseline_ms * sorted.back(),
               static_cast<int>(n)};
  r.time_ms.paired = baseline_ms * r.rel_time_median;
  r.rounds = {kAtriumScale, batch, std::move(ratios)};
  table::set_intervals(r);
  return r;
}

}  // namespace aovar::test
