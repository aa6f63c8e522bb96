// Reports: the seed pairs are matched on rows that differ in one axis only, the Markdown lists the front,
// the HTML is self-contained (inline SVG, data URIs, no network).
#include <gtest/gtest.h>

#include "report/report.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

table::CostRow row(const std::string& variant, std::map<std::string, std::string> axes, double ms, double rmse) {
  table::CostRow r;
  r.variant = variant;
  r.axes = std::move(axes);
  r.scene = "s";
  r.view = "v";
  r.backend = "lavapipe";
  r.time_ms.min = ms;
  r.time_ms.n = 3;
  r.error = table::ErrorStat{rmse, rmse, 20, 0.9, 0, rmse};
  return r;
}

TEST(Report, SeedPairsMatchRowsDifferingInOneAxis) {
  table::CostTable t;
  t.rows.push_back(row("a-bsep", {{"algorithm", "alchemy"}, {"blur", "separable"}, {"samples", "8"}}, 10, 0.050));
  t.rows.push_back(row("a-bbil", {{"algorithm", "alchemy"}, {"blur", "bilateral"}, {"samples", "8"}}, 12, 0.052));
  t.rows.push_back(row("b-bsep", {{"algorithm", "alchemy"}, {"blur", "separable"}, {"samples", "16"}}, 20, 0.040));
  t.rows.push_back(row("b-bbil", {{"algorithm", "alchemy"}, {"blur", "bilateral"}, {"samples", "16"}}, 30, 0.044));
  // Differs in two axes from every other row: must not be matched.
  t.rows.push_back(row("c-bbil", {{"algorithm", "gtao"}, {"blur", "bilateral"}, {"samples", "32"}}, 99, 0.9));
  table::mark_pareto(t);
  auto pairs = report::seed_pairs(t);
  auto blur = std::find_if(pairs.begin(), pairs.end(), [](const auto& p) { return p.axis == "blur"; });
  ASSERT_NE(blur, pairs.end());
  EXPECT_EQ(blur->pairs, 2);
  EXPECT_DOUBLE_EQ(blur->time_delta_pct, 35.0);  // median of +20 % and +50 %
  EXPECT_NEAR(blur->rmse_delta, 0.003, 1e-12);   // median of +0.002 and +0.004
  EXPECT_NE(blur->seed.find("§5.7"), std::string::npos);
  for (const auto& p : pairs)
    if (p.axis != "blur") EXPECT_EQ(p.pairs, 0) << p.title;

  auto md = report::markdown_report(t);
  EXPECT_NE(md.find("| a-bsep | 10.00 | 0.0500"), std::string::npos) << md;  // on the front
  EXPECT_EQ(md.find("| c-bbil |"), std::string::npos) << "dominated rows are not on the front";

  TempDir dir;
  report::write_reports(t, dir.path());
  auto html = util::read_file(dir / "report.html").value();
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("a-bsep"), std::string::npos);
  // Self-contained: the only URL is the SVG namespace.
  std::string rest = html;
  for (std::size_t at; (at = rest.find("http://www.w3.org/2000/svg")) != std::string::npos;) rest.erase(at, 26);
  EXPECT_EQ(rest.find("http"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "report.md"));
}

}  // namespace
}  // namespace aovar::test
