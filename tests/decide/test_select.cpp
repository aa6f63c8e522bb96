// `aovar select` (src/decide/select.cpp): budget, max error, near ties, the worst view, the CLI's exit status.
#include <gtest/gtest.h>

#include "cost_rows.h"
#include "decide/select.h"
#include "table/table.h"
#include "selection.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::decide {
namespace {
using table::CostTable;  // select's input; its rows are built by test::plain_row

CostTable select_table() {
  CostTable t;
  t.rows = {test::plain_row("fast", 1.0, 0.20), test::plain_row("mid", 2.0, 0.10), test::plain_row("good", 3.0, 0.05), test::plain_row("best", 5.0, 0.01),
            test::plain_row("meh", 2.5, 0.12), test::plain_row("worse", 4.0, 0.30)};
  return t;
}

TEST(Select, BudgetPicksLowestErrorWithin) {
  SelectQuery q;
  q.budget_ms = 3.0;
  auto s = select(select_table(), q);
  ASSERT_TRUE(test::chose(s, "good"));
  EXPECT_EQ(test::variants_of(s.runners_up), (std::vector<std::string>{"mid", "meh", "fast"}));
  EXPECT_NE(s.text.find("choice: good"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("within 3.000 ms"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("rmse +0.05000 (+100.0%) at -1.000 ms (-33.3%)"), std::string::npos) << s.text;
}

TEST(Select, MaxErrorPicksCheapestMeetingIt) {
  SelectQuery q;
  q.max_error = 0.1;
  auto s = select(select_table(), q);
  ASSERT_TRUE(test::chose(s, "mid"));
  ASSERT_EQ(s.runners_up.size(), 2u);
  EXPECT_EQ(s.runners_up[0].variant, "good");
  EXPECT_NE(s.text.find("costs +1.000 ms (+50.0%)"), std::string::npos) << s.text;
}

TEST(Select, NamesANearTieThatIsMuchCheaperOrMuchBetter) {
  CostTable t = select_table();
  t.rows.push_back(test::plain_row("cheap_tie", 2.0, 0.0505));   // 33 % faster than "good" for +1 % error
  t.rows.push_back(test::plain_row("almost", 2.9, 0.0501));      // only 3 % faster: not worth a line
  SelectQuery q;
  q.budget_ms = 3.0;
  auto s = select(t, q);
  ASSERT_TRUE(test::chose(s, "good"));
  ASSERT_TRUE(s.consider);
  EXPECT_EQ(s.consider->variant, "cheap_tie");
  EXPECT_NE(s.text.find("consider: cheap_tie [lavapipe] is -33.3% in time with +1.0% rmse"), std::string::npos) << s.text;
  q.tolerance = 0.005;  // +1 % error is now too much
  EXPECT_FALSE(select(t, q).consider);
  // Max error: "mid" (2 ms, 0.10) is the cheapest; "better_tie" has 40 % less error for +1 % time.
  CostTable m = select_table();
  m.rows.push_back(test::plain_row("better_tie", 2.02, 0.06));
  SelectQuery e;
  e.max_error = 0.1;
  s = select(m, e);
  EXPECT_EQ(s.choice->variant, "mid");
  ASSERT_TRUE(s.consider);
  EXPECT_EQ(s.consider->variant, "better_tie");
  // Without a near tie nothing is suggested.
  EXPECT_FALSE(select(select_table(), e).consider);
}

TEST(Select, NothingSatisfiesNamesTheNearest) {
  SelectQuery q;
  q.budget_ms = 0.5;
  auto s = select(select_table(), q);
  EXPECT_FALSE(s.ok);
  ASSERT_TRUE(s.nearest);
  EXPECT_EQ(s.nearest->variant, "fast");
  EXPECT_NE(s.text.find("the fastest is fast"), std::string::npos) << s.text;
  SelectQuery e;
  e.max_error = 0.001;
  s = select(select_table(), e);
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.nearest->variant, "best");
  EXPECT_NE(s.text.find("the lowest error is best"), std::string::npos) << s.text;
}

TEST(Select, UsesTheWorstViewUnlessAViewIsGiven) {
  CostTable t;
  // "spiky" is excellent on view a but bad on b; "steady" is fine on both.
  t.rows = {test::plain_row("spiky", 1.0, 0.01, "a"), test::plain_row("spiky", 1.1, 0.40, "b"), test::plain_row("steady", 1.2, 0.05, "a"),
            test::plain_row("steady", 1.5, 0.06, "b")};
  SelectQuery q;
  q.budget_ms = 2.0;
  auto s = select(t, q);
  ASSERT_TRUE(test::chose(s, "steady"));
  EXPECT_EQ(s.choice->time_ms, 1.5);
  EXPECT_EQ(s.choice->rmse, 0.06);
  q.view = "a";
  s = select(t, q);
  EXPECT_EQ(s.choice->variant, "spiky");
  q.budget_ms = 1.4;  // steady's worst time is 1.5: only spiky fits
  q.view.clear();
  s = select(t, q);
  EXPECT_EQ(s.choice->variant, "spiky");
}

// Exit 0 with a choice, 1 (the check asked for failed) when nothing satisfies, 2 (an error) for a missing table.
TEST(Select, CliExitsOneAndNamesTheNearest) {
  test::TempDir dir;
  write_json(select_table(), dir / "cost_table.json");
  std::string table = " --table " + (dir / "cost_table.json").string();
  auto ok = test::run_aovar("select" + table + " --budget-ms 3");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("choice: good"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("runners-up:"), std::string::npos) << ok.output;
  auto none = test::run_aovar("select" + table + " --budget-ms 0.5");
  EXPECT_EQ(none.status, 1) << none.output;
  EXPECT_NE(none.output.find("no variant fits the budget"), std::string::npos) << none.output;
  EXPECT_NE(none.output.find("fast"), std::string::npos) << none.output;
  auto strict = test::run_aovar("select" + table + " --max-error 0.001");
  EXPECT_EQ(strict.status, 1) << strict.output;
  EXPECT_NE(strict.output.find("the lowest error is best"), std::string::npos) << strict.output;
  auto missing = test::run_aovar("select --table " + (dir / "nope.json").string() + " --budget-ms 1");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.output.find("nope.json"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace aovar::decide
