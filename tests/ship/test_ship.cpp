// `aovar ship` (issue 35): the race's elimination rule on synthetic rows, and one whole run on a built-in
// scene: what it records, that a re-run reuses every round, and that its build line generates the choice.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <filesystem>
#include <random>

#include <fmt/format.h>

#include "ship/bounded_estimate.h"
#include "ship/holdout.h"
#include "ship/race.h"
#include "ship/ship.h"
#include "cost_rows.h"

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

// A variant whose rows copy an eliminated one's (the same code: mediump where the driver ignores it) goes
// with it; left in, the next round would measure it on its own.
TEST(ShipRace, ACopyOfAnEliminatedVariantIsEliminatedWithIt) {
  table::CostTable t;
  t.rows.push_back(test::timed_row("fast-accurate", rounds(1.00, 1), 0.050));
  t.rows.push_back(test::timed_row("slow-worse-hp", rounds(1.50, 2), 0.060));
  auto copy = test::timed_row("slow-worse-mp", rounds(1.50, 2), 0.060);
  copy.same_code_as = "slow-worse-hp";
  t.rows.push_back(copy);
  auto kept_copy = test::timed_row("fast-accurate-mp", rounds(1.00, 1), 0.050);
  kept_copy.same_code_as = "fast-accurate";
  t.rows.push_back(kept_copy);
  const auto es = ship::dominated_beyond_noise(t);
  ASSERT_EQ(es.size(), 1u) << "a copy is no candidate of its own";
  const auto copies = ship::same_code_eliminations(t, es);
  ASSERT_EQ(copies.size(), 1u);
  EXPECT_EQ(copies[0].variant, "slow-worse-mp");
  EXPECT_EQ(copies[0].by, "fast-accurate");
  EXPECT_EQ(copies[0].reason.rfind("runs the same code as slow-worse-hp, slower", 0), 0u) << copies[0].reason;
}

TEST(ShipBatch, TheDefaultBatchShrinksWithTheFrameButNotBelowASweeps) {
  EXPECT_EQ(ship::batch_for({320, 180}), 128);
  EXPECT_EQ(ship::batch_for({640, 360}), 128);
  EXPECT_EQ(ship::batch_for({1280, 720}), 32);
  EXPECT_EQ(ship::batch_for({1920, 1080}), 24);
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

// The margin (race.h): a slowdown of 1.05x beyond the noise eliminates at margin 1 but not at 1.10, whose
// interval must lie wholly above 1.10; a 1.50x slowdown eliminates at both.
TEST(ShipRace, AMarginKeepsSlowdownsWhoseIntervalReachesBelowIt) {
  table::CostTable t;
  t.rows.push_back(test::timed_row("fast-accurate", rounds(1.00, 11), 0.050));
  t.rows.push_back(test::timed_row("a-bit-slower", rounds(1.05, 12), 0.060));
  t.rows.push_back(test::timed_row("much-slower", rounds(1.50, 13), 0.070));
  const auto none = ship::dominated_beyond_noise(t, "", 1.0);
  EXPECT_TRUE(eliminated(none, "a-bit-slower"));
  EXPECT_TRUE(eliminated(none, "much-slower"));
  const auto margin = ship::dominated_beyond_noise(t, "", 1.10);
  EXPECT_FALSE(eliminated(margin, "a-bit-slower"));
  ASSERT_TRUE(eliminated(margin, "much-slower"));
  EXPECT_NE(margin[0].reason.find("1.10x margin"), std::string::npos) << margin[0].reason;
}

// The screen's untraced elimination (bounded_estimate.h): a candidate is dropped only when a traced one with
// strictly less error has an estimate below its bound; it is never traced; equal error, a bound below the
// estimate, or the budget's variant keep it.
// A candidate before the estimate: its key, still error and ALU bound.
ship::BoundCandidate untraced(const char* key, double error, double bound) {
  ship::BoundCandidate c;
  c.key = key;
  c.error = error;
  c.bound = bound;
  return c;
}

TEST(ShipBound, OnlyACandidateSurelyBeatenIsLeftUntraced) {
  std::vector<ship::BoundCandidate> c = {
      untraced("costly-worse", 0.060, 0.30),   // bound above a's estimate: beaten
      untraced("a", 0.050, 0.10),              // the most accurate: traced first
      untraced("cheap-worse", 0.070, 0.15),    // bound below a's estimate: could still be faster, traced
      untraced("tied-error", 0.050, 0.40),     // as accurate as a: never beaten by it
      untraced("budget", 0.080, 0.50),         // the budget's variant: always traced
  };
  const std::map<std::string, double> est = {{"a", 0.20}, {"cheap-worse", 0.18}, {"tied-error", 0.45},
                                             {"costly-worse", 0.35}, {"budget", 0.6}};
  std::vector<std::string> traced;
  ship::eliminate_by_bound(c, "budget", 1, 1, [&](const std::vector<ship::BoundCandidate*>& chunk, int) {
    for (auto* x : chunk) {
      x->est = est.at(x->key);
      traced.push_back(x->key);
    }
  });
  // By error, then bound; costly-worse is skipped.
  EXPECT_EQ(traced, (std::vector<std::string>{"a", "tied-error", "cheap-worse", "budget"}));
  auto find = [&](const std::string& k) {
    return *std::find_if(c.begin(), c.end(), [&](const ship::BoundCandidate& x) { return x.key == k; });
  };
  EXPECT_EQ(find("costly-worse").beaten_by, "a");
  EXPECT_FALSE(find("costly-worse").traced);
  for (const char* kept : {"a", "cheap-worse", "tied-error", "budget"}) {
    EXPECT_TRUE(find(kept).beaten_by.empty()) << kept;
    EXPECT_TRUE(find(kept).traced) << kept;
  }
}

// The traffic other candidates' traces simulated raises a bound before its own trace (issue 55): a candidate
// that this refined bound already shows beaten is never traced; one it does not is traced as before.
TEST(ShipBound, ACandidateWhoseSharedPassesAlreadyBeatItIsNeverTraced) {
  std::vector<ship::BoundCandidate> c = {untraced("a", 0.05, 0.1), untraced("shares-slow-passes", 0.06, 0.1),
                                         untraced("shares-fast-passes", 0.07, 0.1)};
  const std::map<std::string, double> refined = {{"a", 0.1}, {"shares-slow-passes", 0.3}, {"shares-fast-passes", 0.15}};
  const std::map<std::string, double> est = {{"a", 0.2}, {"shares-slow-passes", 0.35}, {"shares-fast-passes", 0.18}};
  std::vector<std::string> traced;
  ship::eliminate_by_bound(
      c, "", 1, 1,
      [&](const std::vector<ship::BoundCandidate*>& chunk, int) {
        for (auto* x : chunk) x->est = est.at(x->key), traced.push_back(x->key);
      },
      {},
      [&](const std::vector<ship::BoundCandidate*>& chunk, int) {
        for (auto* x : chunk)
          if (refined.at(x->key) > x->bound) x->bound = refined.at(x->key), x->bound_cached = true;
      });
  EXPECT_EQ(traced, (std::vector<std::string>{"a", "shares-fast-passes"}));
  EXPECT_EQ(c[1].key, "shares-slow-passes");
  EXPECT_EQ(c[1].beaten_by, "a");
  EXPECT_TRUE(c[1].bound_cached);
  EXPECT_FALSE(c[1].traced);
  EXPECT_TRUE(c[2].beaten_by.empty());
}

// Two stages (two training views): a candidate whose first view's estimate already exceeds a more accurate
// variant's worst-view estimate is eliminated without its second view; the others get both.
TEST(ShipBound, ACandidateBeatenOnItsFirstViewIsNotTracedOnTheSecond) {
  std::vector<ship::BoundCandidate> c = {untraced("a", 0.05, 0.1), untraced("slow-first-view", 0.06, 0.1), untraced("fast", 0.07, 0.1)};
  const std::map<std::string, std::array<double, 2>> views = {
      {"a", {0.20, 0.25}}, {"slow-first-view", {0.30, 0.10}}, {"fast", {0.15, 0.18}}};
  std::vector<std::string> second;
  ship::eliminate_by_bound(c, "", 1, 2, [&](const std::vector<ship::BoundCandidate*>& chunk, int stage) {
    for (auto* x : chunk) {
      x->est = std::max(x->est, views.at(x->key)[stage]);
      if (stage == 1) second.push_back(x->key);
    }
  });
  EXPECT_EQ(second, (std::vector<std::string>{"a", "fast"}));
  EXPECT_EQ(c[1].key, "slow-first-view");
  EXPECT_EQ(c[1].beaten_by, "a");
  EXPECT_TRUE(c[1].bound_traced);
  EXPECT_DOUBLE_EQ(c[0].est, 0.25) << "the worst view";
  EXPECT_TRUE(c[2].beaten_by.empty());
}

// Views in turn (issue 55): errors start as the first view's, a lower bound on the worst, and so is the first
// view's traced estimate. A candidate that a traced, more accurate one beats on them is dropped before its other
// views render; the others are completed (error raised to the worst view) before their other views are traced,
// and checked again on it. The survivors are those of the rule run on every view's error from the start.
TEST(ShipBound, ACandidateBeatenOnItsFirstViewsErrorIsNeverRenderedOnTheOthers) {
  struct Truth {
    double first_error, worst_error, alu, first_est, other_est;
  };
  const std::map<std::string, Truth> truth = {
      {"a", {0.04, 0.05, 0.10, 0.20, 0.18}},
      {"dropped-early", {0.06, 0.09, 0.25, 0.30, 0.30}},      // beaten by a on its ALU bound alone
      {"traced-out", {0.065, 0.07, 0.10, 0.35, 0.10}},         // beaten by a once its first view is traced
      {"worse-elsewhere", {0.045, 0.12, 0.05, 0.22, 0.25}},    // looks better than a there; its worst is not
      {"cheap", {0.07, 0.08, 0.05, 0.10, 0.12}},               // faster than a: on the front
      {"budget", {0.08, 0.10, 0.40, 0.50, 0.50}}};
  auto run = [&](bool in_turn, std::vector<std::string>& completed, std::vector<std::string>& second_traced) {
    std::vector<ship::BoundCandidate> c;
    for (const auto& [key, t] : truth) {
      c.push_back(untraced(key.c_str(), in_turn ? t.first_error : t.worst_error, t.alu));
      c.back().complete = !in_turn;
    }
    auto trace = [&](const std::vector<ship::BoundCandidate*>& chunk, int stage) {
      for (auto* x : chunk) {
        if (stage == 1) {
          EXPECT_TRUE(x->complete) << x->key << " traced on its other views before they were rendered";
          second_traced.push_back(x->key);
        }
        x->est = std::max(x->est, stage == 0 ? truth.at(x->key).first_est : truth.at(x->key).other_est);
      }
    };
    auto complete = [&](const std::vector<ship::BoundCandidate*>& chunk) {
      for (auto* x : chunk) {
        EXPECT_FALSE(x->complete) << x->key;
        x->error = truth.at(x->key).worst_error, x->complete = true, completed.push_back(x->key);
      }
    };
    if (in_turn) ship::eliminate_by_bound(c, "budget", 1, 2, trace, complete);
    else ship::eliminate_by_bound(c, "budget", 1, 2, trace);
    std::map<std::string, bool> beaten;  // who beats it may differ: the fastest traced by then
    for (const auto& x : c) beaten[x.key] = !x.beaten_by.empty();
    return beaten;
  };
  std::vector<std::string> completed, second, none, second_all_views;
  const auto in_turn = run(true, completed, second);
  const auto all_views = run(false, none, second_all_views);
  EXPECT_EQ(in_turn, all_views) << "the same eliminations";
  EXPECT_TRUE(in_turn.at("dropped-early"));
  EXPECT_TRUE(in_turn.at("traced-out"));
  EXPECT_TRUE(in_turn.at("worse-elsewhere")) << "beaten once its worst view is known";
  EXPECT_FALSE(in_turn.at("cheap"));
  EXPECT_FALSE(in_turn.at("a"));
  for (const char* never : {"dropped-early", "traced-out"})
    EXPECT_EQ(std::count(completed.begin(), completed.end(), never), 0) << never << " rendered on the others";
  EXPECT_EQ(std::count(completed.begin(), completed.end(), "worse-elsewhere"), 1);
  EXPECT_EQ(std::count(second.begin(), second.end(), "worse-elsewhere"), 0) << "dropped before its other views' trace";
  EXPECT_TRUE(none.empty());
}

// Held-out still rows (no time): each variant on two held-out views, its worst is its rmse.
table::CostTable stills(const std::map<std::string, std::array<double, 2>>& rmse) {
  table::CostTable t;
  for (const auto& [k, e] : rmse)
    for (int v = 0; v < 2; ++v) {
      table::CostRow r = test::point_row(k, 0, e[v]);
      r.view = v ? "closeup" : "overview";
      r.time_ms = {};
      t.rows.push_back(r);
    }
  return t;
}

// The race's order: per view, how many screen rows are both more accurate and faster (rel_time_median);
// the front first. A row without an error or a time is not ranked.
TEST(ShipRace, TheScreensFrontIsRankedFirstOnEachView) {
  table::CostTable screen;
  const auto add = [&](const std::string& k, const std::string& view, double rel, double rmse) {
    table::CostRow r = test::point_row(k, 10 * rel, rmse);
    r.view = view;
    r.rel_time_median = rel;
    screen.rows.push_back(r);
  };
  add("fast-rough", "overview", 0.5, 0.09);  // front
  add("slow-fine", "overview", 2.0, 0.03);   // front
  add("mid", "overview", 1.0, 0.05);         // front
  add("beaten", "overview", 1.2, 0.06);      // mid is faster and more accurate
  add("worst", "overview", 2.5, 0.10);       // all four beat it
  add("mid", "closeup", 1.0, 0.05);
  add("beaten", "closeup", 0.9, 0.06);       // faster here: front on this view
  add("untimed", "closeup", 0.0, 0.01);      // no time: not ranked
  const auto ranks = ship::screen_ranks(screen);
  const std::map<std::pair<std::string, std::string>, int> expected{
      {{"fast-rough", "overview"}, 0}, {{"slow-fine", "overview"}, 0}, {{"mid", "overview"}, 0},
      {{"beaten", "overview"}, 1},     {{"worst", "overview"}, 4},     {{"mid", "closeup"}, 0},
      {{"beaten", "closeup"}, 0}};
  EXPECT_EQ(*ranks, expected);
}

// --budget-of: a survivor is timed on the held-out views only when its worst held-out rmse is within the
// budget's own plus select's tolerance: the budget's variant always fits, so nothing less accurate is chosen.
TEST(ShipHoldout, BudgetOfTimesOnlyWhatIsAtMostTheBudgetsErrorPlusTheTolerance) {
  const auto t = stills({{"base", {0.050, 0.060}},       // worst 0.060: the bound is 0.0612
                         {"better", {0.070, 0.040}},     // worst 0.070 on the overview: not timed
                         {"within-tol", {0.061, 0.030}}, // 0.061 <= 0.0612: timed (select may name it)
                         {"accurate", {0.030, 0.035}},
                         {"no-still", {0.0, 0.0}}});
  table::CostTable partial = t;
  std::erase_if(partial.rows, [](const table::CostRow& r) { return r.variant == "no-still"; });
  decide::SelectQuery q;
  q.budget_of = "base";
  const std::vector<std::string> survivors = {"accurate", "base", "better", "no-still", "within-tol"};
  const ship::HoldoutPlan p = ship::plan_holdout_timing(partial, survivors, q);
  EXPECT_EQ(p.timed, (std::vector<std::string>{"accurate", "base", "no-still", "within-tol"}));
  EXPECT_EQ(p.by_error, (std::vector<std::string>{"base", "accurate", "within-tol", "no-still"}))
      << "the budget first, then by error, the unrendered last";
  EXPECT_EQ(test::variants_of(p.untimed), std::vector<std::string>{"better"});
  EXPECT_DOUBLE_EQ(p.untimed[0].rmse, 0.070);
  EXPECT_NE(p.rule.find("base"), std::string::npos) << p.rule;
}

TEST(ShipHoldout, MaxErrorTimesWhatFitsOrElseTheNearest) {
  const auto t = stills({{"a", {0.02, 0.03}}, {"b", {0.05, 0.04}}, {"c", {0.09, 0.01}}});
  decide::SelectQuery q;
  q.max_error = 0.045;
  EXPECT_EQ(ship::plan_holdout_timing(t, {"a", "b", "c"}, q).timed, std::vector<std::string>{"a"});
  q.max_error = 0.01;  // nothing fits: the lowest error is timed, for select's nearest
  const ship::HoldoutPlan none = ship::plan_holdout_timing(t, {"a", "b", "c"}, q);
  EXPECT_EQ(none.timed, std::vector<std::string>{"a"});
  EXPECT_EQ(test::variants_of(none.untimed), (std::vector<std::string>{"b", "c"}));
}

// Staged in order of error: the choice among the most accurate ones timed is the choice among all once every
// survivor after them is less accurate than it beyond the tolerance.
TEST(ShipHoldout, TheTimingStopsOnceNoSurvivorLeftCouldBeChosenOrConsidered) {
  ship::HoldoutPlan plan;
  plan.by_error = {"base", "a", "b", "c", "d"};
  plan.rmse = {{"base", 0.06}, {"a", 0.03}, {"b", 0.04}, {"c", 0.0405}, {"d", 0.05}};
  table::CostTable rows;
  rows.rows.push_back(test::timed_row("base", std::vector<double>(8, 1.0), 0.06));
  rows.rows.push_back(test::timed_row("a", rounds(1.5, 11), 0.03));  // the most accurate, over the budget
  rows.rows.push_back(test::timed_row("b", rounds(0.8, 12), 0.04));  // fits: the choice so far
  decide::SelectQuery q;
  q.budget_of = "base";
  EXPECT_FALSE(ship::holdout_settled(rows, plan, 3, q)) << "c (0.0405) is within 2 % of b's 0.04: select may name it";
  rows.rows.push_back(test::timed_row("c", rounds(0.9, 13), 0.0405));
  const auto bound = ship::holdout_settled(rows, plan, 4, q);
  ASSERT_TRUE(bound);
  EXPECT_DOUBLE_EQ(*bound, 0.04 * 1.02) << "d (0.05) cannot be chosen";
  q = {};
  q.max_error = 0.045;
  EXPECT_FALSE(ship::holdout_settled(rows, plan, 4, q)) << "--max-error's plan is its cut: all of it is timed";
  EXPECT_TRUE(ship::holdout_settled(rows, plan, 5, q));
}

// The staging itself, without a sweep: each call times the first 8 more of the plan; it stops at the first
// call after which no survivor left could be chosen, and records each left with why.
TEST(ShipHoldout, TheStagedTimingExtendsByChunksUntilSettledAndRecordsTheRest) {
  ship::HoldoutPlan plan;
  plan.by_error = {"base"};
  plan.rmse = {{"base", 0.06}};
  for (int i = 0; i < 20; ++i) {  // v00..v19, rmse 0.030 + i/1000: the first ten over the budget, the rest fit
    const std::string k = fmt::format("v{:02}", i);
    plan.by_error.push_back(k);
    plan.rmse[k] = 0.030 + 0.001 * i;
  }
  std::vector<std::size_t> calls;
  const auto time_first = [&](const std::vector<std::string>& keys) {
    calls.push_back(keys.size());
    EXPECT_TRUE(std::equal(keys.begin(), keys.end(), plan.by_error.begin())) << "a prefix of the plan, in its order";
    table::CostTable rows;
    for (const auto& k : keys) {
      const int i = k == "base" ? -1 : std::stoi(k.substr(1));
      rows.rows.push_back(test::timed_row(k, i < 0 ? std::vector<double>(8, 1.0) : rounds(i < 10 ? 1.5 : 0.8, unsigned(i + 1)),
                                          plan.rmse.at(k)));
    }
    return rows;
  };
  decide::SelectQuery q;
  q.budget_of = "base";
  const ship::HoldoutTiming t = ship::time_in_error_order(plan, q, time_first);
  // 8 timed (base, v00..v06): only base fits, and v07..v19 are within its 0.06: not settled. 16 (up to v14):
  // v10 (0.040) fits and v15.. (0.045 and up) are beyond its 2 %.
  EXPECT_EQ(calls, (std::vector<std::size_t>{8, 16}));
  EXPECT_EQ(t.timed, 16u);
  EXPECT_EQ(t.rows.rows.size(), 16u);
  ASSERT_EQ(t.untimed.size(), 5u);
  EXPECT_EQ(t.untimed.front().variant, "v15");
  EXPECT_DOUBLE_EQ(t.untimed.front().rmse, 0.045);
  EXPECT_NE(t.untimed.front().reason.find("0.04000"), std::string::npos) << t.untimed.front().reason;

  // A first call that returns no row of the budget's variant decides nothing yet: the next chunk is timed.
  calls.clear();
  int call = 0;
  const auto without_budget_first = [&](const std::vector<std::string>& keys) {
    table::CostTable rows = time_first(keys);
    if (call++ == 0) std::erase_if(rows.rows, [](const table::CostRow& r) { return r.variant == "base"; });
    return rows;
  };
  EXPECT_EQ(ship::time_in_error_order(plan, q, without_budget_first).timed, 16u);
  EXPECT_EQ(calls, (std::vector<std::size_t>{8, 16}));

  // Nothing to time: no call (no keys would select the whole space).
  calls.clear();
  EXPECT_EQ(ship::time_in_error_order({}, q, time_first).timed, 0u);
  EXPECT_TRUE(calls.empty());
}

TEST(ShipHoldout, ABudgetInMillisecondsOrAMissingBudgetVariantTimesEverySurvivor) {
  const auto t = stills({{"a", {0.02, 0.03}}, {"b", {0.05, 0.04}}});
  decide::SelectQuery q;
  q.budget_ms = 1.0;
  EXPECT_EQ(ship::plan_holdout_timing(t, {"a", "b"}, q).timed, (std::vector<std::string>{"a", "b"}));
  q = {};
  q.budget_of = "not-rendered";
  const ship::HoldoutPlan p = ship::plan_holdout_timing(t, {"a", "b"}, q);
  EXPECT_EQ(p.timed, (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(p.untimed.empty());
}

}  // namespace
