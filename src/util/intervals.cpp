#include "util/intervals.h"

#include <algorithm>

namespace aovar::util {
namespace {

// P(Bin(n, 1/2) <= j), summed in log space so that n in the thousands (--reps auto) stays exact enough.
double binomial_half_cdf(int n, int j) {
  double sum = 0;
  for (int i = 0; i <= j; ++i)
    sum += std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) - n * std::log(2.0));
  return sum;
}

// The two-sided standard normal quantile for `level` (0.95 -> 1.95996), by bisection on erfc: only a few
// levels are ever asked for, and <cmath> has no inverse.
double normal_quantile(double level) {
  const double tail = (1 - level) / 2;
  double lo = 0, hi = 10;
  for (int i = 0; i < 100; ++i) {
    double mid = (lo + hi) / 2;
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > tail ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

}  // namespace

int min_samples_for_median(double level) {
  int n = 1;
  while (1 - 2 * binomial_half_cdf(n, 0) < level) ++n;
  return n;
}

Interval median_interval(std::vector<double> samples, double level) {
  const int n = static_cast<int>(samples.size());
  if (n < min_samples_for_median(level)) return {};
  int k = 1;  // the largest k with coverage >= level
  while (k + 1 <= (n + 1) / 2 && 1 - 2 * binomial_half_cdf(n, k) >= level) ++k;
  std::sort(samples.begin(), samples.end());
  return {samples[static_cast<std::size_t>(k - 1)], samples[static_cast<std::size_t>(n - k)]};
}

Shift shift_interval(const std::vector<double>& a, const std::vector<double>& b, double level) {
  Shift s;
  if (a.empty() || b.empty()) return s;
  std::vector<double> d;
  d.reserve(a.size() * b.size());
  for (double x : a)
    for (double y : b) d.push_back(x - y);
  std::sort(d.begin(), d.end());
  const std::size_t mn = d.size();
  s.estimate = mn % 2 ? d[mn / 2] : (d[mn / 2 - 1] + d[mn / 2]) / 2;
  if (a.size() < 4 || b.size() < 4) return s;
  const double m = static_cast<double>(a.size()), n = static_cast<double>(b.size());
  const double sd = std::sqrt(m * n * (m + n + 1) / 12);
  // k - 1 differences below the interval: the lower critical value of U (continuity-corrected).
  const auto k = static_cast<std::size_t>(std::max(1.0, std::floor(m * n / 2 - normal_quantile(level) * sd - 0.5) + 1));
  if (k > mn / 2) return s;
  s.ci = {d[k - 1], d[mn - k]};
  return s;
}

}  // namespace aovar::util
