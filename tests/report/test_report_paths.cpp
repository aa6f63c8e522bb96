// Names that become paths, in `report` (issue 20): only images under the table's folder are embedded, and the
// front is recomputed instead of trusted from the file.
#include <gtest/gtest.h>

#include <filesystem>

#include "cost_rows.h"
#include "decide/pareto.h"
#include "report/report.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

// A row whose algorithm axis is its variant's first word ("alchemy-a": alchemy).
table::CostRow algorithm_row(const std::string& variant, double ms, double rmse) {
  return axes_row(variant, {{"algorithm", variant.substr(0, variant.find('-'))}}, ms, rmse);
}

// Before: a row naming /etc/passwd (or a symlink to it) put the file into report.html as base64.
TEST(PathNames, ReportEmbedsOnlyImagesUnderTheTablesFolder) {
  TempDir dir;
  util::write_atomic(dir / "secret.txt", "not an image, not the report's business\n");
  fs::create_directories(dir / "table" / "images");
  fs::create_symlink(dir / "secret.txt", dir / "table" / "images" / "link.png");
  table::CostTable t;
  t.rows.push_back(algorithm_row("alchemy-a", 10, 0.1));
  t.rows[0].images = {"images/a.pfm", (dir / "secret.txt").string(), "images/link.png"};
  decide::mark_pareto(t);
  ASSERT_TRUE(t.rows[0].pareto);
  report::write_reports(t, dir / "table");
  const std::string html = util::read_file(dir / "table" / "report.html").value();
  EXPECT_EQ(html.find("data:image/png;base64,"), std::string::npos) << "no outside file is read";
  EXPECT_NE(html.find("outside the table folder: not embedded"), std::string::npos) << html.substr(0, 200);
}

// Before: `pareto: true` on a row without an error made the report read an empty optional (UB, 0.0000).
TEST(PathNames, ReportRecomputesTheFrontInsteadOfTrustingTheFile) {
  table::CostTable t;
  t.rows.push_back(algorithm_row("alchemy-fast", 10, 0.10));
  t.rows.push_back(algorithm_row("gtao-slow-bad", 30, 0.20));  // dominated
  t.rows.push_back(algorithm_row("sao-noerror", 5, 0.0));
  t.rows[2].error.reset();
  for (auto& r : t.rows) r.pareto = true;  // as a hand-edited table says
  const std::string md = report::markdown_report(t);
  EXPECT_NE(md.find("| alchemy-fast |"), std::string::npos) << md;
  EXPECT_EQ(md.find("| gtao-slow-bad |"), std::string::npos) << "dominated: not on the front\n" << md;
  EXPECT_EQ(md.find("| sao-noerror |"), std::string::npos) << "no error: never on the front\n" << md;
  TempDir dir;
  EXPECT_NO_THROW(report::write_reports(t, dir.path()));
}

}  // namespace
}  // namespace aovar::test
