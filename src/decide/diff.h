#pragma once
// `aovar diff`: per-variant deltas between two cost tables (shader-db style), each decided beyond the noise.
#include <string>
#include <vector>

#include "table/table.h"
#include "util/intervals.h"

namespace aovar::decide {

struct Delta {
  std::string key;   // table::CostRow::key()
  double a = 0, b = 0;
  // 100 (b - a) / a; 0 when both are 0, +-inf when only a is 0. Time decided by rounds: 100 (ratio - 1) of
  // compare_time's ratio to the baseline, free of the drift between the two runs that a and b keep.
  double pct = 0;
  // Time: the 95 % interval of pct (from compare_time's interval of b / a); unknown where the row was
  // decided by the threshold (no rounds on either side) and for rmse and ssim (deterministic).
  util::Interval pct_ci;
  const char* verdict = "unchanged";  // "helped", "hurt", "unchanged" or "inconclusive" (see MetricDiff)
  bool by_threshold = false;          // time: decided by |change| > 2 % (no rounds on either side)
};

struct MetricDiff {
  std::string metric;          // "time_ms" (paired, else min), "error.rmse", "error.ssim"
  bool higher_is_better = false;
  // Time: helped / hurt = faster / slower beyond the noise (compare_time), inconclusive = the interval of
  // the ratio holds 1; rows without an interval are decided by the threshold (then unchanged when within
  // it) and counted in by_threshold too.
  int helped = 0, hurt = 0, unchanged = 0, inconclusive = 0;
  int by_threshold = 0;
  double total_a = 0, total_b = 0;  // sums over the rows in both tables
  double mean_pct = 0;              // mean of the per-row percentages (finite ones)
  std::vector<Delta> top_helped, top_hurt;  // up to 10 each, largest relative change first
  std::vector<Delta> rows;                  // every row in both tables, by key
};

struct TableDiff {
  std::vector<MetricDiff> metrics;
  std::vector<std::string> only_a, only_b;  // row keys
  int common = 0;
};

// Rows match by table::CostRow::key(). Time: compare_time(b, a) on the rows' rounds (the decision time: paired, else
// min); rows without rounds on both sides (older tables) fall back to |Δ| > 2 %. rmse and ssim: |Δ| > 1e-4
// absolute. Time skips predicted rows; error metrics skip rows without an error on either side.
TableDiff diff_tables(const table::CostTable& a, const table::CostTable& b);
std::string format_diff(const TableDiff& d, const std::string& name_a, const std::string& name_b);
// `aovar diff --json`: the same as one JSON document, with every common row's verdict (not only the top 10).
nlohmann::json to_json(const TableDiff& d, const std::string& name_a, const std::string& name_b);

}  // namespace aovar::decide
