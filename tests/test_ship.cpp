// `aovar ship` (issue 35): the race's elimination rule on synthetic rows, and one whole run on a built-in
// scene: what it records, that a re-run reuses every round, and that its build line generates the choice.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "ship/race.h"
#include "ship/ship.h"
#include "timed_rows.h"

namespace {
using namespace aovar;

// `ratio` per round with a +-1 % spread from a fixed generator: 8 rounds.
std::vector<double> rounds(double ratio, unsigned seed) {
  std::mt19937 gen(seed);
  std::vector<double> out;
  for (int i = 0; i < 8; ++i) out.push_back(ratio * (1 + 0.01 * (2 * double(gen()) / 4294967295.0 - 1)));
  return out;
}

bool eliminated(const std::vector<ship::Elimination>& es, const std::string& variant) {
  return std::any_of(es.begin(), es.end(), [&](const ship::Elimination& e) { return e.variant == variant; });
}

TEST(ShipRace, AClearlyDominatedCandidateIsDroppedAndATiedOneKept) {
  table::CostTable t;
  t.rows.push_back(test::timed_row("fast-accurate", rounds(1.00, 1), 0.050));
  t.rows.push_back(test::timed_row("slow-worse", rounds(1.50, 2), 0.060));   // slower beyond the noise, more error
  t.rows.push_back(test::timed_row("tied-worse", rounds(1.002, 3), 0.070));  // more error, but tied on time
  t.rows.push_back(test::timed_row("slow-better", rounds(2.00, 4), 0.040));  // slower, but more accurate
  const auto es = ship::dominated_beyond_noise(t);
  EXPECT_TRUE(eliminated(es, "slow-worse"));
  EXPECT_FALSE(eliminated(es, "tied-worse"));
  EXPECT_FALSE(eliminated(es, "slow-better"));
  EXPECT_FALSE(eliminated(es, "fast-accurate"));
  ASSERT_EQ(es.size(), 1u);
  EXPECT_EQ(es[0].by, "fast-accurate");
  EXPECT_NE(es[0].reason.find("beyond the noise"), std::string::npos) << es[0].reason;
}

TEST(ShipRace, EqualErrorIsNotDomination) {
  table::CostTable t;
  t.rows.push_back(test::timed_row("a", rounds(1.0, 5), 0.050));
  t.rows.push_back(test::timed_row("b", rounds(1.6, 6), 0.050));  // slower beyond the noise, the same error
  EXPECT_TRUE(ship::dominated_beyond_noise(t).empty());
}

TEST(ShipRace, TheWorstViewDecides) {
  // c is faster than d and more accurate on the overview, but its worst view (closeup) has more error than d's.
  table::CostTable t;
  t.rows.push_back(test::timed_row("c", rounds(1.0, 7), 0.030));
  auto c_close = test::timed_row("c", rounds(1.0, 8), 0.090);
  c_close.view = "closeup";
  t.rows.push_back(c_close);
  t.rows.push_back(test::timed_row("d", rounds(1.6, 9), 0.080));
  EXPECT_TRUE(ship::dominated_beyond_noise(t).empty());
  t.rows.pop_back();
  t.rows.push_back(test::timed_row("d", rounds(1.6, 9), 0.095));  // now worse than c's worst view too
  EXPECT_TRUE(eliminated(ship::dominated_beyond_noise(t), "d"));
}

}  // namespace
