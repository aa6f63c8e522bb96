// The intervals every time comparison rests on (util/intervals.h): the sign-test interval of the median and
// the Mann-Whitney interval of a shift, with their coverage on skewed samples.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "util/intervals.h"

namespace aovar::test {
namespace {

TEST(Intervals, SignTestIntervalOfTheMedianUsesTheBinomialRanks) {
  EXPECT_EQ(util::min_samples_for_median(), 6);
  EXPECT_FALSE(util::median_interval({1, 2, 3, 4, 5}).known()) << "5 samples cannot reach 95 %";
  EXPECT_EQ(util::median_interval({6, 1, 5, 2, 4, 3}), (util::Interval{1, 6}));
  // n = 10: [x_(2), x_(9)] (coverage 97.9 %; [x_(3), x_(8)] would be 89.1 %).
  EXPECT_EQ(util::median_interval({10, 1, 9, 2, 8, 3, 7, 4, 6, 5}), (util::Interval{2, 9}));
  // n = 100: ranks 40 and 61 (the classic table value).
  std::vector<double> v(100);
  for (int i = 0; i < 100; ++i) v[i] = 100 - i;
  EXPECT_EQ(util::median_interval(v), (util::Interval{40, 61}));
}

TEST(Intervals, CoverageHoldsOnSkewedSamples) {
  // Exponential samples (skewed, like frame times with descheduled rounds): the median's interval should
  // hold the true median (ln 2) in at least 95 % of 2,000 trials; Mann-Whitney's the true shift 0.
  std::mt19937 rng(3);
  std::exponential_distribution<double> e(1.0);
  int held_median = 0, held_shift = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> a(12), b(10);
    for (double& x : a) x = e(rng);
    for (double& x : b) x = e(rng);
    held_median += util::median_interval(a).contains(std::log(2.0));
    held_shift += util::shift_interval(a, b).ci.contains(0.0);
  }
  EXPECT_GE(held_median, 0.95 * trials - 20);  // 20: a 2-sigma allowance of the binomial count
  EXPECT_GE(held_shift, 0.95 * trials - 20);
  EXPECT_LE(held_shift, trials - 20) << "an interval holding the truth every time is too wide to decide";
}

TEST(Intervals, MannWhitneyFindsAClearShiftAndItsSize) {
  std::vector<double> a = {10, 11, 12, 13, 14, 15, 16, 17}, b = {0, 1, 2, 3, 4, 5, 6, 7};
  util::Shift s = util::shift_interval(a, b);
  EXPECT_DOUBLE_EQ(s.estimate, 10);
  ASSERT_TRUE(s.ci.known());
  EXPECT_GT(s.ci.lo, 5);
  EXPECT_LT(s.ci.hi, 15);
  EXPECT_FALSE(util::shift_interval({1, 2, 3}, b).ci.known()) << "3 samples are too few";
}

}  // namespace
}  // namespace aovar::test
