// The intervals every time comparison rests on (util/intervals.h, table/time_compare.h), and the seed pairs'
// verdicts built on them (report/seed_pairs.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "report/seed_pairs.h"
#include "table/time_compare.h"
#include "util/intervals.h"

namespace aovar::test {
namespace {

// Per-round ratios to the baseline: `median` times log-normal noise of `noise` (relative), fixed seed.
std::vector<double> ratios(double median, double noise, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> z(0, noise);
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(median * std::exp(z(rng)));
  return out;
}

table::CostRow timed(const std::string& variant, std::vector<double> r, const std::string& id,
                     const std::string& view = "v", double baseline_ms = 10) {
  table::CostRow row;
  row.variant = variant;
  row.scene = "s";
  row.view = view;
  row.backend = "lavapipe";
  row.rounds = {"base@s/" + view, id, std::move(r)};
  std::vector<double> copy = row.rounds.ratios;
  row.rel_time_median = util::summarize(copy).median;
  row.time_ms.min = row.time_ms.median = baseline_ms * row.rel_time_median;
  row.time_ms.n = static_cast<int>(row.rounds.ratios.size());
  row.time_ms.paired = baseline_ms * row.rel_time_median;
  table::set_intervals(row);
  return row;
}

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

TEST(CompareTime, NoiseIsATieAndAClearDifferenceIsNot) {
  const auto base = ratios(1.0, 0.02, 10, 1);
  // Same batch: round i against round i. 0.5 % apart under 2 % noise: tied.
  auto a = timed("a", ratios(1.000, 0.02, 10, 2), "b/0"), b = timed("b", ratios(1.005, 0.02, 10, 3), "b/0");
  auto c = compare_time(a, b);
  EXPECT_TRUE(c.tied()) << table::ratio_text(c) << " " << c.method;
  EXPECT_TRUE(c.ci.contains(1.0));
  // 20 % apart: faster, whichever way it is paired.
  auto fast = timed("fast", ratios(0.80, 0.02, 10, 4), "b/0");
  EXPECT_EQ(compare_time(fast, a).verdict, table::TimeVerdict::faster);
  EXPECT_EQ(compare_time(a, fast).verdict, table::TimeVerdict::slower);
  auto fast_elsewhere = timed("fast2", ratios(0.80, 0.02, 10, 5), "b/1");
  EXPECT_EQ(compare_time(fast_elsewhere, a).verdict, table::TimeVerdict::faster);
  (void)base;
}

TEST(CompareTime, PairedRoundsCancelWhatTheRoundsShare) {
  // Two rows whose rounds drift together by +-15 % (a busy host) but one is always 4 % slower: paired round by
  // round that is clear, while the same samples from different batches are not separable.
  std::vector<double> drift = ratios(1.0, 0.15, 12, 7), slower;
  for (double d : drift) slower.push_back(d * 1.04);
  auto a = timed("a", drift, "b/0"), b = timed("b", slower, "b/0");
  auto paired = compare_time(b, a);
  EXPECT_STREQ(paired.method, "paired rounds");
  EXPECT_EQ(paired.verdict, table::TimeVerdict::slower) << table::ratio_text(paired);
  EXPECT_NEAR(paired.ratio, 1.04, 1e-9);
  auto b_elsewhere = timed("b", slower, "b/1");
  auto separate = compare_time(b_elsewhere, a);
  EXPECT_STREQ(separate.method, "separate rounds");
  EXPECT_TRUE(separate.tied()) << table::ratio_text(separate);
}

TEST(CompareTime, AgainstTheBaselineIsTheRowsOwnInterval) {
  auto base = timed("base", std::vector<double>(10, 1.0), table::Rounds::kAll);
  auto a = timed("a", ratios(1.10, 0.02, 10, 8), "b/0");
  auto c = compare_time(a, base);
  EXPECT_EQ(c.verdict, table::TimeVerdict::slower);
  EXPECT_DOUBLE_EQ(c.ratio, a.rel_time_median);
  EXPECT_EQ(c.ci, a.rel_time_ci);
  // Rows without rounds (tables written before them, estimates): the point decides, without an interval.
  table::CostRow old_a = a, old_b = base;
  old_a.rounds = {};
  old_b.rounds = {};
  auto p = compare_time(old_a, old_b);
  EXPECT_STREQ(p.method, "point estimates");
  EXPECT_FALSE(p.ci.known());
  EXPECT_EQ(p.verdict, table::TimeVerdict::slower);
}

TEST(CompareTime, ParetoTreatsATieAsEqualTime) {
  // Point-wise a is faster, but within the noise of b; b has the lower error: b dominates a.
  auto a = timed("a", ratios(1.00, 0.03, 10, 9), "b/0"), b = timed("b", ratios(1.01, 0.03, 10, 10), "b/0");
  ASSERT_TRUE(compare_time(a, b).tied());
  ASSERT_LT(a.time_ms.decision(), b.time_ms.decision());
  a.error = metrics::ErrorStats{};
  a.error->rmse = 0.05;
  b.error = metrics::ErrorStats{};
  b.error->rmse = 0.04;
  auto fast = timed("fast", ratios(0.5, 0.03, 10, 11), "b/0");
  fast.error = metrics::ErrorStats{};
  fast.error->rmse = 0.09;
  auto twin = b;
  twin.variant = "b-twin";
  twin.same_code_as = "b";
  std::vector<table::CostRow> rows = {a, b, fast, twin};
  table::mark_pareto(rows);
  EXPECT_FALSE(rows[0].pareto) << "tied on time with a lower-error row";
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_TRUE(rows[2].pareto) << "faster beyond the noise";
  EXPECT_FALSE(rows[3].pareto) << "a same-code row stands behind its representative";
}

TEST(SeedPairs, VerdictsFollowTheIntervalsAndTheSeedsDirection) {
  table::CostTable t;
  auto add = [&](const std::string& variant, std::map<std::string, std::string> axes, std::vector<double> r) {
    auto row = timed(variant, std::move(r), "b/0");
    row.axes = std::move(axes);
    t.rows.push_back(std::move(row));
  };
  // Progressive (seed: faster) clearly faster: reproduced. Bilateral blur (seed: slower) clearly faster:
  // refuted. r32f against r16f within the noise: inconclusive here.
  add("full", {{"progressive", "false"}, {"k", "1"}}, ratios(1.0, 0.02, 10, 20));
  add("prog", {{"progressive", "true"}, {"k", "1"}}, ratios(0.6, 0.02, 10, 21));
  add("sep", {{"blur", "separable"}, {"k", "2"}}, ratios(1.0, 0.02, 10, 22));
  add("bil", {{"blur", "bilateral"}, {"k", "2"}}, ratios(0.8, 0.02, 10, 23));
  add("d16", {{"depth_format", "r16f"}, {"k", "3"}}, ratios(1.0, 0.03, 10, 24));
  add("d32", {{"depth_format", "r32f"}, {"k", "3"}}, ratios(1.003, 0.03, 10, 25));
  auto find = [&](const std::string& axis) {
    for (const auto& f : report::seed_pairs(t))
      if (f.axis == axis) return f;
    ADD_FAILURE() << axis;
    return report::PairFinding{};
  };
  EXPECT_EQ(find("progressive").verdict, "reproduced");
  EXPECT_EQ(find("blur").verdict, "refuted");
  EXPECT_EQ(find("depth_format").verdict, "inconclusive here");
  EXPECT_TRUE(find("progressive").ci.known());
  EXPECT_LT(find("progressive").ci.hi, 1.0);
  EXPECT_EQ(find("normals").verdict, "-") << "no pair: no verdict";
  // Estimates have no interval: the sign decides.
  auto est = report::seed_pairs(t, [](const table::CostRow& r) { return r.time_ms.decision(); });
  for (const auto& f : est)
    if (f.axis == "depth_format") EXPECT_FALSE(f.ci.known());
}

}  // namespace
}  // namespace aovar::test
