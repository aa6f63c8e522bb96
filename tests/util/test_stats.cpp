// util::summarize and util::percentile (src/util/stats.h): nearest-rank percentiles, the same rank
// in both (src/profile's depth, error and angle percentiles use percentile).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "util/stats.h"

namespace aovar::test {
namespace {

TEST(Stats, NearestRankPercentiles) {
  EXPECT_EQ(util::percentile({}, 0.5), 0.0);
  const std::vector<double> v = {5, 1, 4, 2, 3, 10, 9, 8, 7, 6};  // 1..10
  EXPECT_EQ(util::percentile(v, 0.0), 1.0);
  EXPECT_EQ(util::percentile(v, 0.05), 1.0);  // ceil(0.5) = rank 1
  EXPECT_EQ(util::percentile(v, 0.5), 5.0);   // rank 5
  EXPECT_EQ(util::percentile(v, 0.51), 6.0);  // rank 6
  EXPECT_EQ(util::percentile(v, 0.95), 10.0);
  EXPECT_EQ(util::percentile(v, 1.0), 10.0);
  EXPECT_EQ(util::percentile(v, 7.0), 10.0);  // clamped
  const auto summary = util::summarize(v);  // the same ranks
  EXPECT_EQ(summary.n, 10);
  EXPECT_EQ(summary.min, 1.0);
  EXPECT_EQ(summary.median, 5.0);
  EXPECT_EQ(summary.p90, 9.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 100);
  for (int n : {1, 2, 3, 17, 1000}) {
    std::vector<double> s(n);
    for (auto& x : s) x = u(rng);
    auto t = util::summarize(s);
    EXPECT_EQ(util::percentile(s, 0.5), t.median) << n;
    EXPECT_EQ(util::percentile(s, 0.9), t.p90) << n;
    EXPECT_EQ(util::percentile(s, 0.0), t.min) << n;
  }
}

}  // namespace
}  // namespace aovar::test
