// The Pareto front and the worst view (src/decide/pareto.cpp).
#include <gtest/gtest.h>

#include <map>

#include "cost_rows.h"
#include "decide/pareto.h"

namespace aovar::decide {
namespace {
using table::CostRow;
using test::on_front;
using test::plain_row;

TEST(Pareto, FrontWithTies) {
  std::vector<CostRow> rows = {
      plain_row("A", 1, 0.5), plain_row("G", 1, 0.6),                    // G: same time, higher error
      plain_row("B", 2, 0.3), plain_row("C", 2, 0.4),                    // C: dominated by B
      plain_row("D", 3, 0.3),                                      // D: same error as B, slower
      plain_row("E", 4, 0.1), plain_row("F", 4, 0.1),                    // identical points: both on the front
      plain_row("H", 5, 0.2),                                      // dominated by E
      plain_row("N", 0.1, std::nullopt),                           // no error: never on the front
      plain_row("X", 9, 0.9, "other"),                             // alone in its view: on its front
  };
  mark_pareto(rows);
  EXPECT_TRUE(on_front(rows, "A"));
  EXPECT_FALSE(on_front(rows, "G"));
  EXPECT_TRUE(on_front(rows, "B"));
  EXPECT_FALSE(on_front(rows, "C"));
  EXPECT_FALSE(on_front(rows, "D"));
  EXPECT_TRUE(on_front(rows, "E"));
  EXPECT_TRUE(on_front(rows, "F"));
  EXPECT_FALSE(on_front(rows, "H"));
  EXPECT_FALSE(on_front(rows, "N"));
  EXPECT_TRUE(on_front(rows, "X", "other"));
  // Deterministic: the input order does not matter.
  std::vector<CostRow> reversed(rows.rbegin(), rows.rend());
  mark_pareto(reversed);
  for (const auto& r : reversed) EXPECT_EQ(r.pareto, on_front(rows, r.variant, r.view)) << r.variant;
}

TEST(Pareto, WorstViewAggregatesMaxErrorAndTime) {
  std::vector<CostRow> rows = {plain_row("P", 1, 0.10, "a"), plain_row("P", 2, 0.05, "b"),   // worst: 2 ms, 0.10
                               plain_row("Q", 1.5, 0.02, "a"), plain_row("Q", 1.2, 0.30, "b"),  // worst: 1.5 ms, 0.30
                               plain_row("R", 3, 0.08, "a"), plain_row("R", 3, 0.09, "b")};  // worst: 3 ms, 0.09
  auto w = worst_view(rows);
  ASSERT_EQ(w.size(), 3u);
  std::map<std::string, CostRow> by;
  for (const auto& r : w) by[r.variant] = r;
  EXPECT_EQ(by["P"].time_ms.min, 2);
  EXPECT_EQ(by["P"].error->rmse, 0.10);
  EXPECT_EQ(by["Q"].time_ms.min, 1.5);
  EXPECT_EQ(by["Q"].error->rmse, 0.30);
  EXPECT_EQ(by["P"].view, "worst(a,b)");
  EXPECT_TRUE(by["Q"].pareto);   // fastest
  EXPECT_TRUE(by["P"].pareto);
  EXPECT_TRUE(by["R"].pareto);   // lowest worst-case error
}

}  // namespace
}  // namespace aovar::decide
