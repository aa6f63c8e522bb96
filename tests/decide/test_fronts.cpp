// generate --from-table's choice (decide/fronts.h): per target the variants select answers for some budget.
// The AMD device map the generated pick table embeds and the manifest check: tests/compile/test_from_table.cpp.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "compile/pick_table.h"
#include "cost_rows.h"
#include "decide/fronts.h"
#include "decide/select.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar {
namespace {

// Seven variants on two views of lavapipe, each with a navi21 estimate that orders them differently from
// the measured times: the two fronts differ.
table::CostTable two_target_table() {
  struct Spec { const char* key; double ms, rmse, est; };
  const std::vector<Spec> specs = {{"a", 1.0, 0.30, 4.0}, {"b", 2.0, 0.20, 1.0}, {"c", 3.0, 0.25, 2.0},
                                   {"d", 4.0, 0.10, 3.5}, {"e", 5.0, 0.12, 0.5}, {"f", 6.0, 0.05, 6.0},
                                   {"g", 7.0, 0.05, 7.0}};
  table::CostTable t;
  for (const auto& s : specs)
    for (const char* view : {"overview", "corner"}) {
      // The corner view is slower and worse: the worst view decides, as select's candidates do.
      const bool corner = std::string(view) == "corner";
      table::CostRow r = test::point_row(s.key, s.ms * (corner ? 1.1 : 1.0), s.rmse * (corner ? 1.2 : 1.0));
      r.view = view;
      r.gpu["navi21"].est_ms = s.est;
      t.rows.push_back(r);
    }
  return t;
}

// The strict Pareto front of the worst-view points, fastest first: each point has less error than every
// faster one. An oracle written apart from select.
std::vector<std::string> staircase(const std::vector<decide::Candidate>& all) {
  std::vector<decide::Candidate> sorted = all;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    return std::tie(a.time_ms, a.rmse) < std::tie(b.time_ms, b.rmse);
  });
  std::vector<std::string> out;
  double best = INFINITY;
  for (const auto& c : sorted)
    if (c.rmse < best) out.push_back(c.variant), best = c.rmse;
  return out;
}

TEST(TableFronts, EachTargetsFrontIsTheParetoStaircaseOfItsOwnTimes) {
  const auto t = two_target_table();
  for (const auto& [target, family] : std::vector<std::pair<std::string, bool>>{{"lavapipe", false}, {"navi21", true}}) {
    decide::SelectQuery q = decide::query_for(target, family);
    const decide::TargetFront front = decide::budget_front(t, target, family);
    EXPECT_EQ(test::variants_of(front.points), staircase(decide::candidates(t, q))) << target;
    for (std::size_t i = 1; i < front.points.size(); ++i) {
      EXPECT_LT(front.points[i - 1].time_ms, front.points[i].time_ms) << target;
      EXPECT_GT(front.points[i - 1].rmse, front.points[i].rmse) << target;
    }
  }
  EXPECT_NE(test::variants_of(decide::budget_front(t, "lavapipe", false).points),
            test::variants_of(decide::budget_front(t, "navi21", true).points));
}

TEST(TableFronts, TheLastPointWithinABudgetIsSelectsAnswer) {
  const auto t = two_target_table();
  for (const auto& [target, family] : std::vector<std::pair<std::string, bool>>{{"lavapipe", false}, {"navi21", true}}) {
    const decide::TargetFront front = decide::budget_front(t, target, family);
    for (double budget = 0.25; budget < 9; budget += 0.25) {
      decide::SelectQuery q = decide::query_for(target, family);
      q.budget_ms = budget;
      const decide::Selection s = decide::select(t, q);
      const decide::FrontPoint* last = nullptr;
      for (const auto& p : front.points)
        if (p.time_ms <= budget) last = &p;
      ASSERT_EQ(s.ok, last != nullptr) << target << " " << budget;
      if (last) {
        EXPECT_EQ(s.choice->variant, last->variant) << target << " " << budget;
      }
    }
  }
}

TEST(TableFronts, KeepsTheUnionOfTheRequestedFrontsOrSelectsPicks) {
  const auto t = two_target_table();
  auto is_family = [](const std::string& name) { return name != "lavapipe"; };
  const decide::TableKeep all = decide::keep_from_table(t, {"t.json", {}, {}}, is_family);
  ASSERT_EQ(all.fronts.size(), 2u);
  EXPECT_EQ(all.fronts[0].target, "navi21");  // families first, then backends
  EXPECT_EQ(all.fronts[1].target, "lavapipe");
  std::vector<std::string> expected = test::variants_of(all.fronts[0].points);
  for (const auto& k : test::variants_of(all.fronts[1].points)) expected.push_back(k);
  std::sort(expected.begin(), expected.end());
  expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
  EXPECT_EQ(all.keys, expected);

  decide::TableRequest pick{"t.json", {"lavapipe"}, {}};
  pick.pick.budget_ms = 4.5;
  const decide::TableKeep picked = decide::keep_from_table(t, pick, is_family);
  ASSERT_EQ(picked.keys, std::vector<std::string>{"d"});  // d: 4.4 ms worst view, rmse 0.12
}

TEST(TableFronts, ATargetWithoutRowsOrAPickThatNothingFitsIsOneLineNamingTheTable) {
  const auto t = two_target_table();
  auto is_family = [](const std::string& name) { return name != "lavapipe" && name != "gles"; };
  for (const char* target : {"navi22", "gles"}) {
    const std::string what = test::thrown_message<std::runtime_error>([&] {
      decide::keep_from_table(t, {"sweep/cost_table.json", {target}, {}}, is_family);
    });
    EXPECT_EQ(what.rfind("sweep/cost_table.json: ", 0), 0u) << what;
    EXPECT_NE(what.find(target), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  decide::TableRequest too_tight{"t.json", {"navi21"}, {}};
  too_tight.pick.budget_ms = 0.1;
  EXPECT_THROW(decide::keep_from_table(t, too_tight, is_family), std::runtime_error);
}

}  // namespace
}  // namespace aovar
