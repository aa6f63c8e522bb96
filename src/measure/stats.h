#pragma once
// Summary statistics of repeated timings: min-of-N is the stable figure on these noisy machines
// (DESIGN.md §4); median and p90 show the spread.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace aovar::measure {

struct TimeStats {
  double min = 0, median = 0, p90 = 0;
  int n = 0;
};

// Nearest-rank percentiles over the samples (copied, sorted). Empty input gives n = 0 and zeros.
TimeStats summarize(std::vector<double> samples);

// The nearest-rank q-percentile (q in [0, 1]) of the samples (copied): the smallest sample with at least q of
// the samples <= it, the rank summarize uses; 0 for no samples. Linear time (nth_element). Inline, so that
// modules below aovar_measure (src/profile, which aovar_measure links) use it without a link cycle.
inline double percentile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0.0;
  const auto n = samples.size();
  const auto rank = static_cast<std::size_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(n)));
  const auto k = std::clamp<std::size_t>(rank, 1, n) - 1;
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k), samples.end());
  return samples[k];
}

}  // namespace aovar::measure
