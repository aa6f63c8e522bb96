#pragma once
// Summary statistics of repeated timings: min-of-N is the stable figure on these noisy machines
// (DESIGN.md §4); median and p90 show the spread.
#include <vector>

namespace aovar::measure {

struct TimeStats {
  double min = 0, median = 0, p90 = 0;
  int n = 0;
};

// Nearest-rank percentiles over the samples (copied, sorted). Empty input gives n = 0 and zeros.
TimeStats summarize(std::vector<double> samples);

}  // namespace aovar::measure
