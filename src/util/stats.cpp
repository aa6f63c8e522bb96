#include "util/stats.h"

#include <algorithm>

namespace aovar::util {

double percentile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0.0;
  const auto n = samples.size();
  const auto rank = static_cast<std::size_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(n)));
  const auto k = std::clamp<std::size_t>(rank, 1, n) - 1;
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k), samples.end());
  return samples[k];
}

TimeStats summarize(std::vector<double> samples) {
  TimeStats s;
  s.n = static_cast<int>(samples.size());
  if (samples.empty()) return s;
  s.min = *std::min_element(samples.begin(), samples.end());
  s.median = percentile(samples, 0.5);
  s.p90 = percentile(samples, 0.9);
  return s;
}

}  // namespace aovar::util
