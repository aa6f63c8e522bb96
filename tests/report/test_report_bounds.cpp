// A report of a large table stays readable (issue 34, point 5): fronts list their 100 fastest rows, charts
// draw at most 2,000 points, and each bounded section says what it left out; a small table is unchanged.
#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>

#include "report/bounds.h"
#include "report/report.h"
#include "table/table.h"

namespace {
using namespace aovar;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// n rows of one scene, view and backend, each slower with less error than the one before (no rounds: the
// point estimates decide), so every row is on the front.
table::CostTable all_on_the_front(int n) {
  table::CostTable t;
  for (int i = 0; i < n; ++i) {
    table::CostRow r;
    r.variant = fmt::format("alchemy-v{:05d}", i);
    r.axes = {{"algorithm", "alchemy"}};
    r.scene = "builtin:atrium";
    r.view = "overview";
    r.backend = "lavapipe";
    r.time_ms = {1.0 + i, 1.0 + i, 1.0 + i, 10};
    metrics::ErrorStats e;
    e.rmse = 1.0 / (1 + i);
    r.error = e;
    t.rows.push_back(r);
  }
  return t;
}

TEST(ReportBounds, ALargeFrontIsListedInPartAndSaysSo) {
  const table::CostTable t = all_on_the_front(3000);
  const std::string md = report::markdown_report(t);
  EXPECT_EQ(count(md, "| alchemy-v"), report::kMaxListed);
  EXPECT_NE(md.find("| alchemy-v00099 |"), std::string::npos);  // the fastest 100
  EXPECT_EQ(md.find("| alchemy-v00100 |"), std::string::npos);
  EXPECT_NE(md.find("(showing 100 of 3000 rows on the front, fastest first; cost_table.json has them all)"),
            std::string::npos);
  const std::string html = report::html_report(t, ".");
  // The Pareto scatter: 2,000 points, all of them front rows (the static-cost scatter has none: no row was
  // analysed), and the note.
  EXPECT_EQ(count(html, "<circle"), report::kMaxCharted);
  EXPECT_NE(html.find("showing 2000 of 3000 rows in the charts"), std::string::npos);
  EXPECT_LT(html.size(), 2'000'000u);
}

TEST(ReportBounds, ChartsKeepTheFrontThenSpreadTheRest) {
  std::vector<table::CostRow> rows(10);
  std::vector<const table::CostRow*> ptrs;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].variant = std::to_string(i);
    rows[i].pareto = i == 7;
    ptrs.push_back(&rows[i]);
  }
  EXPECT_EQ(report::charted(ptrs, 10).size(), 10u);  // fits: all of them
  const auto four = report::charted(ptrs, 4);
  ASSERT_EQ(four.size(), 4u);
  std::vector<std::string> names;
  for (const auto* r : four) names.push_back(r->variant);
  // The front row, then 3 of the 9 others at even steps (the 0th, 3rd and 6th of them), in input order.
  EXPECT_EQ(names, (std::vector<std::string>{"0", "3", "6", "7"}));
}

TEST(ReportBounds, ASmallTableIsNotBounded) {
  const table::CostTable t = all_on_the_front(20);
  EXPECT_EQ(report::markdown_report(t).find("showing"), std::string::npos);
  const std::string html = report::html_report(t, ".");
  EXPECT_EQ(html.find("showing"), std::string::npos);
  EXPECT_EQ(count(html, "<circle"), 20u);
}

}  // namespace
