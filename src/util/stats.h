#pragma once
// Summary statistics of repeated timings: min-of-N is the stable figure on these noisy machines
// (docs/architecture.md, "Timing"); median and p90 show the spread.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "util/intervals.h"

namespace aovar::util {

// One time statistic for every timed thing: a frame, a pass, a cost-table row (in ms).
struct TimeStats {
  double min = 0, median = 0, p90 = 0;
  int n = 0;  // samples; 0 for predicted rows
  // A row's time on its baseline's best-round scale: the baseline's min over every round times the row's
  // median paired ratio (rel_time_median), free of the drift between batches measured at different moments
  // (5-10 % on these hosts). 0 when unknown (not paired, or tables written before it existed).
  double paired = 0;
  // 95 % interval of `paired`: the sign-test interval of the per-round ratios (rel_time_ci) times the same
  // baseline min (util/intervals.h). Unknown (NaN) with fewer than 6 rounds, or for predicted rows.
  Interval paired_ci = {};
  // The time that decides (Pareto, select, the cost model, sorting): paired when known, else min.
  double decision() const { return paired > 0 ? paired : min; }
  bool operator==(const TimeStats&) const = default;
};

// Nearest-rank percentiles over the samples (copied, sorted). Empty input gives n = 0 and zeros.
TimeStats summarize(std::vector<double> samples);

// The nearest-rank q-percentile (q in [0, 1]) of the samples (copied): the smallest sample with at least q of
// the samples <= it, the rank summarize uses; 0 for no samples. Linear time (nth_element).
double percentile(std::vector<double> samples, double q);

}  // namespace aovar::util
