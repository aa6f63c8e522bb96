#pragma once
// Cost-table rows built by hand for the tests of table, report, shard and the CLI: a measured row as measure
// writes it (builtin:atrium / overview on lavapipe at 64x36 with 2 threads, its per-round ratios to the
// baseline, the paired time (baseline min x median ratio), min / median / p90 from the ratios and the
// intervals set_intervals derives from them), rows decided by a point time, and the front they are on.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "table/row_intervals.h"
#include "table/table.h"
#include "util/stats.h"

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

// A row decided by its point time: min `time`, median 1.1x, p90 1.2x (10 frames), rel_time time / 2; with an
// error (mae rmse / 2, psnr 20, ssim 1 - rmse) when rmse is given.
inline table::CostRow plain_row(std::string variant, double time, std::optional<double> rmse,
                                std::string view = "overview", std::string backend = "lavapipe",
                                std::string scene = "builtin:atrium") {
  table::CostRow r;
  r.variant = std::move(variant);
  r.scene = std::move(scene);
  r.view = std::move(view);
  r.backend = std::move(backend);
  r.size = "64x36";
  r.threads = 2;
  r.time_ms = {time, time * 1.1, time * 1.2, 10};
  r.rel_time = time / 2;
  if (rmse) {
    metrics::ErrorStats e;
    e.rmse = *rmse;
    e.mae = *rmse / 2;
    e.psnr = 20;
    e.ssim = 1 - *rmse;
    r.error = e;
  }
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

// A row of scene "s", view "v" on lavapipe with these axes, decided by its min time `ms` (3 rounds), with a
// full error record (rmse, mae = rmse, psnr 20, ssim 0.9).
inline table::CostRow axes_row(const std::string& variant, std::map<std::string, std::string> axes, double ms,
                               double rmse) {
  table::CostRow r;
  r.variant = variant;
  r.axes = std::move(axes);
  r.scene = "s";
  r.view = "v";
  r.backend = "lavapipe";
  r.time_ms.min = ms;
  r.time_ms.n = 3;
  metrics::ErrorStats e;
  e.rmse = e.mae = e.max = rmse;
  e.psnr = 20;
  e.ssim = 0.9;
  r.error = e;
  return r;
}

// Per-round ratios to the baseline: `median` times log-normal noise of `noise` (relative), fixed seed.
inline std::vector<double> lognormal_ratios(double median, double noise, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> z(0, noise);
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(median * std::exp(z(rng)));
  return out;
}

// A row of scene "s" on lavapipe with these per-round ratios in batch `batch`, without an error: its time
// is the baseline's `baseline_ms` times the median ratio, and its intervals follow from the rounds.
inline table::CostRow rounds_row(const std::string& variant, std::vector<double> ratios, const std::string& batch,
                                 const std::string& view = "v", double baseline_ms = 10) {
  table::CostRow row;
  row.variant = variant;
  row.scene = "s";
  row.view = view;
  row.backend = "lavapipe";
  row.rounds = {"base@s/" + view, batch, std::move(ratios)};
  std::vector<double> copy = row.rounds.ratios;
  row.rel_time_median = util::summarize(copy).median;
  row.time_ms.min = row.time_ms.median = baseline_ms * row.rel_time_median;
  row.time_ms.n = static_cast<int>(row.rounds.ratios.size());
  row.time_ms.paired = baseline_ms * row.rel_time_median;
  table::set_intervals(row);
  return row;
}

// Whether the row of `variant` in `view` is on the Pareto front (a failure when there is no such row).
inline bool on_front(const std::vector<table::CostRow>& rows, const std::string& variant,
                     const std::string& view = "overview") {
  for (const auto& r : rows)
    if (r.variant == variant && r.view == view) return r.pareto;
  ADD_FAILURE() << "no row " << variant << " in view " << view;
  return false;
}

// The `variant` of each item (rows, select's candidates, a front's points, a plan's entries), in order: what a
// decision kept, compared in one assertion that prints the whole list when it fails.
template <class Items>
std::vector<std::string> variants_of(const Items& items) {
  std::vector<std::string> out;
  for (const auto& item : items) out.push_back(item.variant);
  return out;
}

}  // namespace aovar::test
