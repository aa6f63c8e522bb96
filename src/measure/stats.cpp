#include "measure/stats.h"

#include <algorithm>
#include <cmath>

namespace aovar::measure {

TimeStats summarize(std::vector<double> samples) {
  TimeStats s;
  s.n = static_cast<int>(samples.size());
  if (samples.empty()) return s;
  std::sort(samples.begin(), samples.end());
  auto rank = [&](double q) {  // nearest rank: the smallest sample with at least q of the samples <= it
    auto i = static_cast<std::size_t>(std::ceil(q * samples.size()));
    return samples[std::clamp<std::size_t>(i, 1, samples.size()) - 1];
  };
  s.min = samples.front();
  s.median = rank(0.5);
  s.p90 = rank(0.9);
  return s;
}

}  // namespace aovar::measure
