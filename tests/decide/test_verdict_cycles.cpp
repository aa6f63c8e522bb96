// Time verdicts that form cycles (issue 34, point 3): "faster beyond the noise" is not transitive, and
// medians of paired ratios can go round (a faster than b, b than c, c than a). select decides among the
// Schwartz set of the verdicts (decide/top_set.h, docs/confidence.md), which is never empty.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include <fmt/format.h>

#include "cost_rows.h"
#include "decide/select.h"
#include "decide/time_compare.h"
#include "decide/top_set.h"
#include "table/table.h"
#include "selection.h"
#include "test_support.h"

namespace {
using namespace aovar;
using namespace aovar::table;
using namespace aovar::decide;
using Graph = std::vector<std::vector<bool>>;  // g[i][j]: i beats j

// The definition, by brute force: x is in the set when everything that reaches x is reached from x.
std::vector<std::size_t> schwartz_by_definition(const Graph& g) {
  const std::size_t n = g.size();
  Graph reach = g;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) reach[i][j] = reach[i][j] || (reach[i][k] && reach[k][j]);
  std::vector<std::size_t> out;
  for (std::size_t x = 0; x < n; ++x) {
    bool top = true;
    for (std::size_t y = 0; y < n; ++y) top = top && (y == x || !reach[y][x] || reach[x][y]);
    if (top) out.push_back(x);
  }
  return out;
}

std::vector<std::size_t> schwartz(const Graph& g, std::size_t pivot) {
  return schwartz_set(g.size(), pivot, [&](std::size_t a, std::size_t b) { return bool(g[a][b]); });
}

Graph with_edges(std::size_t n, const std::vector<std::pair<std::size_t, std::size_t>>& edges) {
  Graph g(n, std::vector<bool>(n, false));
  for (auto [a, b] : edges) g[a][b] = true;
  return g;
}

// A cycle 0 -> 1 -> ... -> k-1 -> 0 of k members, and `tail` more that every cycle member beats.
Graph cycle_with_tail(std::size_t k, std::size_t tail) {
  Graph g = with_edges(k + tail, {});
  for (std::size_t i = 0; i < k; ++i) {
    g[i][(i + 1) % k] = true;
    for (std::size_t t = k; t < k + tail; ++t) g[i][t] = true;
  }
  return g;
}

std::vector<std::size_t> iota(std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

TEST(SchwartzSet, CyclesOfThreeAndMoreAreTheTopWhateverThePivot) {
  for (std::size_t k : {3u, 4u, 5u, 7u}) {
    const Graph g = cycle_with_tail(k, 3);
    for (std::size_t pivot = 0; pivot < g.size(); ++pivot)
      EXPECT_EQ(schwartz(g, pivot), iota(k)) << "cycle of " << k << ", pivot " << pivot;
  }
}

TEST(SchwartzSet, WithoutACycleItIsTheUnbeatenAndItIsNeverEmpty) {
  // A chain 0 > 1 > 2 > 3: only 0. Nothing beats anything: all of them. 0 beats 1, 2 is alone: {0, 2}.
  EXPECT_EQ(schwartz(with_edges(4, {{0, 1}, {1, 2}, {2, 3}}), 3), (std::vector<std::size_t>{0}));
  EXPECT_EQ(schwartz(with_edges(4, {}), 1), iota(4));
  EXPECT_EQ(schwartz(with_edges(3, {{0, 1}}), 1), (std::vector<std::size_t>{0, 2}));
  // A cycle that something outside beats is not the top; a cycle feeding a lower cycle; two top cycles.
  EXPECT_EQ(schwartz(with_edges(4, {{0, 1}, {1, 2}, {2, 0}, {3, 0}}), 0), (std::vector<std::size_t>{3}));
  EXPECT_EQ(schwartz(with_edges(6, {{0, 1}, {1, 2}, {2, 0}, {2, 3}, {3, 4}, {4, 5}, {5, 3}}), 4), iota(3));
  EXPECT_EQ(schwartz(with_edges(6, {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}}), 0), iota(6));
  EXPECT_TRUE(schwartz_set(0, 0, [](std::size_t, std::size_t) { return false; }).empty());
}

TEST(SchwartzSet, MatchesTheDefinitionOnRandomRelations) {
  std::mt19937 gen(34);
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 1 + gen() % 9;
    Graph g = with_edges(n, {});
    const unsigned density = 1 + gen() % 6;  // from sparse (many ties) to dense (many cycles)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        if (i != j && gen() % 8 < density) g[i][j] = true;  // not asymmetric either: "beats" both ways happens
    const auto expected = schwartz_by_definition(g);
    ASSERT_FALSE(expected.empty());
    for (std::size_t pivot = 0; pivot < n; ++pivot) ASSERT_EQ(schwartz(g, pivot), expected) << "trial " << trial;
  }
}

// A row of one batch timed in 3 rounds (too few for an interval: the medians of paired ratios decide).
CostRow three_rounds(const std::string& variant, std::vector<double> ratios, double rmse) {
  return test::timed_row(variant, std::move(ratios), rmse);
}

// Per round, the order of the variants rotates, so each wins against the next in two rounds of three.
CostTable three_cycle() {
  CostTable t;
  t.rows = {three_rounds("a", {1, 2, 3}, 0.05), three_rounds("b", {2, 3, 1}, 0.03), three_rounds("c", {3, 1, 2}, 0.04)};
  return t;
}

bool faster(const CostRow& x, const CostRow& y) { return compare_time(x, y).verdict == TimeVerdict::faster; }

TEST(SelectCycles, AThreeCycleOfVerdictsIsTiedAndTheErrorDecides) {
  const CostTable t = three_cycle();
  ASSERT_TRUE(faster(t.rows[0], t.rows[1]) && faster(t.rows[1], t.rows[2]) && faster(t.rows[2], t.rows[0]))
      << "the premise: a faster than b, b than c, c than a";
  SelectQuery q;
  q.max_error = 0.15;
  const Selection s = select(t, q);
  ASSERT_TRUE(test::chose(s, "b"));  // the lowest rmse of the three
  ASSERT_EQ(s.tied.size(), 2u) << s.text;
  EXPECT_EQ(s.tied[0].variant, "c");
  EXPECT_EQ(s.tied[1].variant, "a");
  // Something faster than all three beyond the noise takes it alone; something slower than all three is out.
  CostTable more = t;
  more.rows.push_back(three_rounds("quick", {0.5, 0.5, 0.5}, 0.1));
  more.rows.push_back(three_rounds("slow", {9, 9, 9}, 0.001));
  const Selection quick = select(more, q);
  ASSERT_TRUE(test::chose(quick, "quick"));
  EXPECT_TRUE(quick.tied.empty()) << quick.text;
}

TEST(SelectCycles, AFourCycleWithChordsIsOneTie) {
  // Round ranks: a b c d / b c d a / c d a b: a > b, b > c, c > d, d > a, and c > a, b > d.
  CostTable t;
  t.rows = {three_rounds("a", {1, 4, 3}, 0.04), three_rounds("b", {2, 1, 4}, 0.05), three_rounds("c", {3, 2, 1}, 0.02),
            three_rounds("d", {4, 3, 2}, 0.03)};
  ASSERT_TRUE(faster(t.rows[0], t.rows[1]) && faster(t.rows[1], t.rows[2]) && faster(t.rows[2], t.rows[3]) &&
              faster(t.rows[3], t.rows[0]));
  SelectQuery q;
  q.max_error = 0.15;
  const Selection s = select(t, q);
  ASSERT_TRUE(test::chose(s, "c"));
  EXPECT_EQ(s.tied.size(), 3u) << s.text;
  SelectQuery b;  // a budget query orders by error and breaks equal errors the same way: never empty either
  b.budget_ms = 10;
  EXPECT_EQ(select(t, b).choice->variant, "c");
}

TEST(SelectCycles, TheCliChoosesOnACyclicTable) {
  test::TempDir dir;
  write_json(three_cycle(), dir / "cost_table.json");
  const auto r = test::run_aovar("select --table " + (dir / "cost_table.json").string() + " --max-error 0.15");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("choice: b [lavapipe]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("tied on time with 2 others"), std::string::npos) << r.output;
}

TEST(SelectRequest, ABudgetOrErrorThatIsNotANumberIsAUsageError) {
  test::TempDir dir;
  write_json(three_cycle(), dir / "cost_table.json");
  const std::string table = " --table " + (dir / "cost_table.json").string();
  for (const char* bad : {"--budget-ms nan", "--budget-ms -1", "--budget-ms 0", "--budget-ms inf", "--budget-ms 1e999",
                          "--budget-ms abc", "--max-error nan", "--max-error -0.1", "--max-error inf",
                          "--max-error 0.1 --tolerance nan"}) {
    const auto r = test::run_aovar(std::string("select") + table + " " + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.output;
    EXPECT_EQ(r.output.find("no variant fits"), std::string::npos) << bad << ": " << r.output;
  }
  // The library refuses them too (its callers are not only the CLI).
  for (double bad : {std::nan(""), -1.0, 0.0, double(INFINITY)}) {
    SelectQuery q;
    q.budget_ms = bad;
    EXPECT_THROW(select(three_cycle(), q), std::runtime_error) << bad;
  }
  SelectQuery q;
  q.max_error = std::nan("");
  EXPECT_THROW(select(three_cycle(), q), std::runtime_error);
}

}  // namespace
