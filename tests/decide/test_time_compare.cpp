// Time comparisons of two rows (decide/time_compare.h): paired rounds, the baseline's own interval, point
// estimates, and the Pareto front's ties. The intervals they rest on: tests/util/test_intervals.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "cost_rows.h"
#include "decide/pareto.h"
#include "decide/time_compare.h"

namespace aovar::test {
namespace {
using namespace aovar::decide;

TEST(CompareTime, NoiseIsATieAndAClearDifferenceIsNot) {
  const auto base = lognormal_ratios(1.0, 0.02, 10, 1);
  // Same batch: round i against round i. 0.5 % apart under 2 % noise: tied.
  auto a = rounds_row("a", lognormal_ratios(1.000, 0.02, 10, 2), "b/0");
  auto b = rounds_row("b", lognormal_ratios(1.005, 0.02, 10, 3), "b/0");
  auto c = compare_time(a, b);
  EXPECT_TRUE(c.tied()) << decide::ratio_text(c) << " " << c.method;
  EXPECT_TRUE(c.ci.contains(1.0));
  // 20 % apart: faster, whichever way it is paired.
  auto fast = rounds_row("fast", lognormal_ratios(0.80, 0.02, 10, 4), "b/0");
  EXPECT_EQ(compare_time(fast, a).verdict, decide::TimeVerdict::faster);
  EXPECT_EQ(compare_time(a, fast).verdict, decide::TimeVerdict::slower);
  auto fast_elsewhere = rounds_row("fast2", lognormal_ratios(0.80, 0.02, 10, 5), "b/1");
  EXPECT_EQ(compare_time(fast_elsewhere, a).verdict, decide::TimeVerdict::faster);
  (void)base;
}

TEST(CompareTime, PairedRoundsCancelWhatTheRoundsShare) {
  // Two rows whose rounds drift together by +-15 % (a busy host) but one is always 4 % slower: paired round by
  // round that is clear, while the same samples from different batches are not separable.
  std::vector<double> drift = lognormal_ratios(1.0, 0.15, 12, 7), slower;
  for (double d : drift) slower.push_back(d * 1.04);
  auto a = rounds_row("a", drift, "b/0"), b = rounds_row("b", slower, "b/0");
  auto paired = compare_time(b, a);
  EXPECT_STREQ(paired.method, "paired rounds");
  EXPECT_EQ(paired.verdict, decide::TimeVerdict::slower) << decide::ratio_text(paired);
  EXPECT_NEAR(paired.ratio, 1.04, 1e-9);
  auto b_elsewhere = rounds_row("b", slower, "b/1");
  auto separate = compare_time(b_elsewhere, a);
  EXPECT_STREQ(separate.method, "separate rounds");
  EXPECT_TRUE(separate.tied()) << decide::ratio_text(separate);
}

TEST(CompareTime, AgainstTheBaselineIsTheRowsOwnInterval) {
  auto base = rounds_row("base", std::vector<double>(10, 1.0), table::Rounds::kAll);
  auto a = rounds_row("a", lognormal_ratios(1.10, 0.02, 10, 8), "b/0");
  auto c = compare_time(a, base);
  EXPECT_EQ(c.verdict, decide::TimeVerdict::slower);
  EXPECT_DOUBLE_EQ(c.ratio, a.rel_time_median);
  EXPECT_EQ(c.ci, a.rel_time_ci);
  // Rows without rounds (tables written before them, estimates): the point decides, without an interval.
  table::CostRow old_a = a, old_b = base;
  old_a.rounds = {};
  old_b.rounds = {};
  auto p = compare_time(old_a, old_b);
  EXPECT_STREQ(p.method, "point estimates");
  EXPECT_FALSE(p.ci.known());
  EXPECT_EQ(p.verdict, decide::TimeVerdict::slower);
}

TEST(CompareTime, ParetoTreatsATieAsEqualTime) {
  // Point-wise a is faster, but within the noise of b; b has the lower error: b dominates a.
  auto a = rounds_row("a", lognormal_ratios(1.00, 0.03, 10, 9), "b/0");
  auto b = rounds_row("b", lognormal_ratios(1.01, 0.03, 10, 10), "b/0");
  ASSERT_TRUE(compare_time(a, b).tied());
  ASSERT_LT(a.time_ms.decision(), b.time_ms.decision());
  a.error = metrics::ErrorStats{};
  a.error->rmse = 0.05;
  b.error = metrics::ErrorStats{};
  b.error->rmse = 0.04;
  auto fast = rounds_row("fast", lognormal_ratios(0.5, 0.03, 10, 11), "b/0");
  fast.error = metrics::ErrorStats{};
  fast.error->rmse = 0.09;
  auto twin = b;
  twin.variant = "b-twin";
  twin.same_code_as = "b";
  std::vector<table::CostRow> rows = {a, b, fast, twin};
  decide::mark_pareto(rows);
  EXPECT_FALSE(rows[0].pareto) << "tied on time with a lower-error row";
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_TRUE(rows[2].pareto) << "faster beyond the noise";
  EXPECT_FALSE(rows[3].pareto) << "a same-code row stands behind its representative";
}

}  // namespace
}  // namespace aovar::test
