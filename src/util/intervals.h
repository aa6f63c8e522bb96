#pragma once
// Distribution-free 95 % confidence intervals for timing comparisons (docs/confidence.md). Frame times on
// these hosts are skewed with outliers (a descheduled thread doubles a frame), so nothing here assumes a
// normal distribution: a median with its sign-test interval, and a location shift with its Mann-Whitney
// interval (Hollander & Wolfe, "Nonparametric Statistical Methods", 3rd ed., §3.1 and §4.3).
#include <cmath>
#include <vector>

namespace aovar::util {

inline constexpr double kConfidence = 0.95;

struct Interval {
  double lo = NAN, hi = NAN;
  bool known() const { return std::isfinite(lo) && std::isfinite(hi); }
  bool contains(double x) const { return known() && lo <= x && x <= hi; }
  bool operator==(const Interval& o) const {
    return (lo == o.lo || (std::isnan(lo) && std::isnan(o.lo))) && (hi == o.hi || (std::isnan(hi) && std::isnan(o.hi)));
  }
};

// The fewest samples for which a two-sided sign-test interval of the median reaches `level` (6 at 95 %:
// the widest interval [x_(1), x_(n)] then covers 1 - 2^(1-n) >= 95 %).
int min_samples_for_median(double level = kConfidence);

// Sign-test interval of the median: [x_(k), x_(n+1-k)] of the sorted samples with the largest k whose
// coverage 1 - 2 P(Bin(n, 1/2) <= k - 1) is at least `level`. It always holds the sample median. Unknown
// (NaN) with fewer than min_samples_for_median() samples.
Interval median_interval(std::vector<double> samples, double level = kConfidence);

// Hodges-Lehmann shift of `a` over `b` (the median of every a_i - b_j) with the Mann-Whitney interval:
// [D_(k), D_(mn+1-k)] of the mn sorted differences, k from the normal approximation of the U statistic's
// distribution (with continuity correction; within one rank of the exact tables for m, n >= 6). Unknown
// (NaN interval) when either side has fewer than 4 samples.
struct Shift {
  double estimate = NAN;
  Interval ci;
};
Shift shift_interval(const std::vector<double>& a, const std::vector<double>& b, double level = kConfidence);

}  // namespace aovar::util
