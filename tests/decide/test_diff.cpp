// `aovar diff` (src/decide/diff.cpp): counts, percentages, rows without rounds.
#include <gtest/gtest.h>

#include "cost_rows.h"
#include "decide/diff.h"
#include "table/table.h"
#include "test_support.h"

namespace aovar::decide {
namespace {
using table::CostTable;
using test::plain_row;

TEST(Diff, CountsAndPercentages) {
  CostTable a, b;
  a.rows = {plain_row("v1", 10, 0.10), plain_row("v2", 10, 0.10), plain_row("v3", 10, 0.10), plain_row("v4", 10, 0.10), plain_row("gone", 1, 0.1)};
  b.rows = {plain_row("v1", 8, 0.10),       // time -20 %: helped; rmse unchanged
            plain_row("v2", 10.1, 0.1002),  // +1 %: unchanged (<= 2 %); rmse +2e-4: hurt
            plain_row("v3", 12.5, 0.05),    // +25 %: hurt; rmse -0.05: helped
            plain_row("v4", 10, 0.10005),   // unchanged both (5e-5 < 1e-4)
            plain_row("new", 1, 0.1)};
  auto d = diff_tables(a, b);
  ASSERT_EQ(d.metrics.size(), 3u);
  const auto& t = d.metrics[0];
  EXPECT_EQ(t.metric, "time_ms");
  EXPECT_EQ(t.by_threshold, 4) << "no rounds: the 2 % threshold decides";
  EXPECT_EQ(t.inconclusive, 0);
  EXPECT_EQ(t.helped, 1);
  EXPECT_EQ(t.hurt, 1);
  EXPECT_EQ(t.unchanged, 2);
  EXPECT_DOUBLE_EQ(t.total_a, 40);
  EXPECT_DOUBLE_EQ(t.total_b, 40.6);
  EXPECT_NEAR(t.mean_pct, (-20 + 1 + 25 + 0) / 4.0, 1e-9);
  ASSERT_EQ(t.top_helped.size(), 1u);
  EXPECT_NEAR(t.top_helped[0].pct, -20, 1e-9);
  EXPECT_EQ(t.top_hurt[0].key.rfind("v3|", 0), 0u);
  EXPECT_NEAR(t.top_hurt[0].pct, 25, 1e-9);
  const auto& e = d.metrics[1];
  EXPECT_EQ(e.metric, "error.rmse");
  EXPECT_EQ(e.helped, 1);
  EXPECT_EQ(e.hurt, 1);
  EXPECT_EQ(e.unchanged, 2);
  EXPECT_NEAR(e.top_helped[0].pct, -50, 1e-9);
  const auto& s = d.metrics[2];  // ssim = 1 - rmse here: higher is better, so the helped/hurt swap sides
  EXPECT_EQ(s.helped, 1);
  EXPECT_EQ(s.hurt, 1);
  ASSERT_EQ(d.only_a.size(), 1u);
  EXPECT_EQ(d.only_a[0].rfind("gone|", 0), 0u);
  ASSERT_EQ(d.only_b.size(), 1u);
  std::string text = format_diff(d, "A.json", "B.json");
  EXPECT_NE(text.find("helped: 1  hurt: 1  unchanged: 2"), std::string::npos) << text;
  EXPECT_NE(text.find("total: 40 -> 40.6 (+1.50%)"), std::string::npos) << text;
  EXPECT_NE(text.find("(-20.00%)"), std::string::npos) << text;
  EXPECT_NE(text.find("only in A (1)"), std::string::npos) << text;

  test::TempDir dir;
  write_json(a, dir / "a.json");
  write_json(b, dir / "b.json");
  auto r = test::run_aovar("diff " + (dir / "a.json").string() + " " + (dir / "b.json").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("rows without rounds decided by"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace aovar::decide
