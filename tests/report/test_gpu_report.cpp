// Selection and reports per GPU (issue 17): `select --target` decides by the row's estimate on
// that family, and the report ranks the methods by it, per pass in the style of RGA, with the seed pairs
// re-judged and the rank agreement between families and against the measured time.
#include <gtest/gtest.h>

#include <cmath>

#include "cost_rows.h"
#include "decide/select.h"
#include "report/gpu_section.h"
#include "report/report.h"
#include "selection.h"
#include "test_support.h"

namespace {
using namespace aovar;
using namespace aovar::table;
using aovar::decide::SelectQuery;

// A row measured here (time `ms`, error `rmse`) with an estimate on each family given.
CostRow row(const std::string& variant, std::map<std::string, std::string> axes, double ms, double rmse,
            std::map<std::string, double> est) {
  CostRow r = test::axes_row(variant, std::move(axes), ms, rmse);
  for (const auto& [family, t] : est) {
    GpuPassCost ao;
    ao.pass = "ao";
    ao.vgprs = 32;
    ao.waves_per_simd = 16;
    ao.texture_ms = t;
    ao.alu_ms = t / 2;
    ao.est_ms = t;
    ao.bound = "texture";
    r.gpu[family] = {"product of " + family, "Mesa test", "1920x1080", "", t, {ao}, {}};
  }
  return r;
}

// On lavapipe "slow_here" is the slowest; on navi21 it is the cheapest: the target decides.
CostTable table_with_estimates() {
  CostTable t;
  t.rows = {row("fast_here", {{"algorithm", "alchemy"}, {"samples", "8"}}, 1.0, 0.05, {{"navi21", 0.9}, {"polaris10", 2.0}}),
            row("mid_here", {{"algorithm", "hbao"}, {"samples", "8"}}, 2.0, 0.04, {{"navi21", 0.6}, {"polaris10", 1.5}}),
            row("slow_here", {{"algorithm", "gtao"}, {"samples", "8"}}, 3.0, 0.03, {{"navi21", 0.3}, {"polaris10", 1.0}}),
            row("no_estimate", {{"algorithm", "sao"}, {"samples", "8"}}, 0.5, 0.02, {})};
  return t;
}

TEST(GpuSelect, TargetDecidesByTheEstimate) {
  SelectQuery q;
  q.max_error = 0.06;
  auto here = select(table_with_estimates(), q);
  ASSERT_TRUE(test::chose(here, "no_estimate"));  // cheapest measured here
  q.target = "navi21";
  auto navi = select(table_with_estimates(), q);
  ASSERT_TRUE(test::chose(navi, "slow_here"));  // cheapest estimated; rows without an estimate are not candidates
  EXPECT_DOUBLE_EQ(navi.choice->time_ms, 0.3);
  EXPECT_NE(navi.text.find("est. on navi21"), std::string::npos) << navi.text;
  EXPECT_NE(navi.text.find("time: the estimate on navi21 (gpu.navi21.est_ms)"), std::string::npos) << navi.text;

  SelectQuery budget;
  budget.budget_ms = 0.7;
  budget.target = "navi21";
  auto b = select(table_with_estimates(), budget);
  ASSERT_TRUE(test::chose(b, "slow_here"));  // lowest error within 0.7 ms estimated (mid_here 0.04 > 0.03)
}

TEST(GpuSelect, UnknownTargetNamesTheFamiliesTheTableHas) {
  SelectQuery q;
  q.max_error = 0.1;
  q.target = "vangogh";
  const std::string m = test::thrown_message<std::runtime_error>([&] { select(table_with_estimates(), q); });
  EXPECT_NE(m.find("'vangogh'"), std::string::npos) << m;
  EXPECT_NE(m.find("navi21, polaris10"), std::string::npos) << m;
  EXPECT_NE(m.find("--gpu vangogh"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << "one line";
}

TEST(GpuReport, RanksMethodsLikeForLikeAndAgreement) {
  CostTable t = table_with_estimates();
  // A second alchemy at 8 samples that differs from the common configuration: not the like-for-like one,
  // although it is cheaper.
  t.rows.push_back(row("alchemy_x4", {{"algorithm", "alchemy"}, {"samples", "8"}, {"resolution", "4"}}, 0.2, 0.2,
                       {{"navi21", 0.1}, {"polaris10", 0.2}}));
  for (auto& r : t.rows)
    if (r.variant != "alchemy_x4") r.axes["resolution"] = "1";
  auto ranking = report::method_ranking(t, "navi21");
  ASSERT_EQ(ranking.size(), 1u) << "only 8 samples in the table";
  ASSERT_EQ(ranking[0].size(), 3u);  // the three methods with an estimate
  EXPECT_EQ(ranking[0][0].variant, "slow_here");
  EXPECT_EQ(ranking[0][2].variant, "fast_here");
  EXPECT_EQ(ranking[0][0].bound, "ao:texture");

  auto families = report::family_agreement(t);
  ASSERT_EQ(families.size(), 1u);
  EXPECT_EQ(families[0].n, 4);
  EXPECT_NEAR(families[0].rho, 1.0, 1e-12);  // navi21 and polaris10 order the four variants alike
  auto measured = report::measured_agreement(t);
  ASSERT_EQ(measured.size(), 2u);
  EXPECT_EQ(measured[0].a, "navi21");
  // Measured ranks 2 3 4 1 against estimated 4 3 2 1: rho = 1 - 6 * 8 / (4 * 15).
  EXPECT_NEAR(measured[0].rho, 0.2, 1e-12);

  std::string md = report::markdown_report(t);
  EXPECT_NE(md.find("## GPU estimate: navi21 (product of navi21)"), std::string::npos) << md;
  EXPECT_NE(md.find("| 1 | gtao | slow_here | 0.300 | ao:texture |"), std::string::npos) << md;
  EXPECT_NE(md.find("| slow_here | ao | 32 |"), std::string::npos) << "the per-pass table: " << md;
  std::string html = report::html_report(t, ".");
  EXPECT_NE(html.find("GPU estimate: polaris10"), std::string::npos);
}

TEST(GpuReport, SeedPairsUseTheEstimate) {
  CostTable t;
  t.rows = {row("a-s8", {{"algorithm", "alchemy"}, {"samples", "8"}}, 10, 0.05, {{"navi21", 1.0}}),
            row("a-s16", {{"algorithm", "alchemy"}, {"samples", "16"}}, 11, 0.04, {{"navi21", 1.8}})};
  auto find = [](const std::vector<report::PairFinding>& pairs) {
    for (const auto& p : pairs)
      if (p.axis == "samples") return p;
    return report::PairFinding{};
  };
  EXPECT_NEAR(find(report::seed_pairs(t)).time_delta_pct, 10.0, 1e-9);      // measured: 10 -> 11 ms
  EXPECT_NEAR(find(report::gpu_seed_pairs(t, "navi21")).time_delta_pct, 80.0, 1e-9);  // estimate: 1.0 -> 1.8 ms
  EXPECT_EQ(find(report::gpu_seed_pairs(t, "polaris10")).pairs, 0);          // no estimate there
  EXPECT_TRUE(report::gpu_markdown(CostTable{}).empty());

  // SAO's z pyramid is its prefilter pass: its share of the estimated frame is reported.
  CostTable sao;
  sao.rows = {row("sao-s8", {{"algorithm", "sao"}, {"samples", "8"}}, 10, 0.05, {{"navi21", 1.0}})};
  GpuPassCost pyramid;
  pyramid.pass = "prefilter";
  pyramid.est_ms = 0.25;
  pyramid.bound = "bandwidth";
  sao.rows[0].gpu["navi21"].passes.insert(sao.rows[0].gpu["navi21"].passes.begin(), pyramid);
  sao.rows[0].gpu["navi21"].est_ms = 1.25;
  EXPECT_NE(report::gpu_markdown(sao).find("the MIP pass is 20.0 % of the estimated SAO frame"), std::string::npos)
      << report::gpu_markdown(sao);
}

}  // namespace

namespace {

// A GL chip (statistics from its compiler, no estimate yet) gets a statistics block: its passes in the
// vendor-neutral counts, fewest AO-pass instructions first, and no ranking by a time it does not have.
TEST(GpuReport, AChipWithStatisticsOnlyShowsThemFewestInstructionsFirst) {
  CostTable t;
  for (const auto& [variant, instructions] : {std::pair{"many", 900.0}, {"few", 300.0}}) {
    CostRow r = test::axes_row(variant, {{"algorithm", "alchemy"}, {"samples", "8"}}, 1.0, 0.05);
    GpuPassCost ao;
    ao.pass = "ao";
    ao.instructions = instructions;
    ao.texture = 8;
    ao.occupancy = 12;
    r.gpu["a320"] = {"", "Mesa 25.0.7", "1920x1080", "", NAN, {ao}, "freedreno"};
    t.rows.push_back(r);
  }
  const std::string md = report::gpu_markdown(t);
  EXPECT_NE(md.find("GPU compiler statistics: a320 (freedreno)"), std::string::npos) << md;
  EXPECT_NE(md.find("No time estimate for this chip yet"), std::string::npos) << md;
  ASSERT_NE(md.find("| few"), std::string::npos) << md;
  EXPECT_LT(md.find("| few"), md.find("| many")) << md;
  EXPECT_NE(md.find("| 300"), std::string::npos) << md;
  EXPECT_EQ(md.find("GPU estimate:"), std::string::npos) << md;
}

}  // namespace
