#pragma once
// The pairs the seeds compared (Sunet 2018, ch. 5: normals, position buffer, reconstruction, depth format,
// progressive, blur; McGuire et al. 2012, Table 1: SAO against Alchemy), re-measured on a table's rows,
// each with the measured effect, its 95 % interval and a verdict against the seed's own direction.
#include <functional>
#include <string>
#include <vector>

#include "report/grid.h"
#include "table/table.h"
#include "util/intervals.h"

namespace aovar::report {

struct PairFinding {
  std::string title, axis, a, b;      // e.g. "RG vs RGB normals", "normals", "rgb8", "rg8"
  std::string seed;                   // the seed's own finding, with its section
  int expected = 0;                   // the seed's direction for b against a: +1 b slower, -1 b faster
  int pairs = 0;                      // matched row pairs
  double time_delta_pct = 0;          // median of (time_b - time_a) / time_a, percent
  double rmse_delta = 0;              // median of rmse_b - rmse_a
  // The median pair's time ratio b / a with its 95 % interval (decide::compare_time; unknown for estimates).
  double ratio = 0;
  util::Interval ci;
  int reproduced = 0, refuted = 0, inconclusive = 0;  // pairs, by their own interval
  // "reproduced": same direction as the seed and the interval excludes no change, in most pairs and refuted
  // in none; "refuted": the opposite; else "inconclusive here". "-" without pairs.
  std::string verdict;
};

// A row's time for a comparison; NaN or <= 0 leaves the row out.
using TimeOf = std::function<double(const table::CostRow&)>;
double measured_time(const table::CostRow& row);  // time_ms.decision(); NaN for predicted rows

// Measured times: each pair judged by decide::compare_time (intervals from the rows' rounds).
std::vector<PairFinding> seed_pairs(const table::CostTable& table);
// Another time (a GPU estimate: deterministic, so a pair is judged by the sign of its difference).
std::vector<PairFinding> seed_pairs(const table::CostTable& table, const TimeOf& time_of);

// The findings as a report table (`what`: the time column's name, "time" or "est. time").
Grid pairs_grid(const std::vector<PairFinding>& findings, const std::string& what);

}  // namespace aovar::report
