#include "measure/stats.h"

#include <algorithm>

namespace aovar::measure {

TimeStats summarize(std::vector<double> samples) {
  TimeStats s;
  s.n = static_cast<int>(samples.size());
  if (samples.empty()) return s;
  s.min = *std::min_element(samples.begin(), samples.end());
  s.median = percentile(samples, 0.5);
  s.p90 = percentile(samples, 0.9);
  return s;
}

}  // namespace aovar::measure
