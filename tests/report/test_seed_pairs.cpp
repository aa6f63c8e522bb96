// The seed pairs' verdicts (report/seed_pairs.h): reproduced, refuted or inconclusive by the intervals of
// rows with real rounds, and by the sign alone for estimates.
#include <gtest/gtest.h>

#include <map>

#include "cost_rows.h"
#include "report/seed_pairs.h"

namespace aovar::test {
namespace {

TEST(SeedPairs, VerdictsFollowTheIntervalsAndTheSeedsDirection) {
  table::CostTable t;
  auto add = [&](const std::string& variant, std::map<std::string, std::string> axes, std::vector<double> r) {
    auto row = rounds_row(variant, std::move(r), "b/0");
    row.axes = std::move(axes);
    t.rows.push_back(std::move(row));
  };
  // Progressive (seed: faster) clearly faster: reproduced. Bilateral blur (seed: slower) clearly faster:
  // refuted. r32f against r16f within the noise: inconclusive here.
  add("full", {{"progressive", "false"}, {"k", "1"}}, lognormal_ratios(1.0, 0.02, 10, 20));
  add("prog", {{"progressive", "true"}, {"k", "1"}}, lognormal_ratios(0.6, 0.02, 10, 21));
  add("sep", {{"blur", "separable"}, {"k", "2"}}, lognormal_ratios(1.0, 0.02, 10, 22));
  add("bil", {{"blur", "bilateral"}, {"k", "2"}}, lognormal_ratios(0.8, 0.02, 10, 23));
  add("d16", {{"depth_format", "r16f"}, {"k", "3"}}, lognormal_ratios(1.0, 0.03, 10, 24));
  add("d32", {{"depth_format", "r32f"}, {"k", "3"}}, lognormal_ratios(1.003, 0.03, 10, 25));
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
    if (f.axis == "depth_format") { EXPECT_FALSE(f.ci.known()); }
}

}  // namespace
}  // namespace aovar::test
