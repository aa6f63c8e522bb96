// Reports: the seed pairs are matched on rows that differ in one axis only, the Markdown lists the front,
// the HTML is self-contained (inline SVG, data URIs, no network) and renders in a headless Chromium.
#include <gtest/gtest.h>

#include <cstdlib>

#include <fmt/format.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "cost_rows.h"
#include "decide/pareto.h"
#include "report/report.h"
#include "test_support.h"
#include "util/fs.h"
#include "variants/manifest.h"

namespace aovar::test {
namespace {

TEST(Report, SeedPairsMatchRowsDifferingInOneAxis) {
  table::CostTable t;
  t.rows.push_back(axes_row("a-bsep", {{"algorithm", "alchemy"}, {"blur", "separable"}, {"samples", "8"}}, 10, 0.050));
  t.rows.push_back(axes_row("a-bbil", {{"algorithm", "alchemy"}, {"blur", "bilateral"}, {"samples", "8"}}, 12, 0.052));
  t.rows.push_back(axes_row("b-bsep", {{"algorithm", "alchemy"}, {"blur", "separable"}, {"samples", "16"}}, 20, 0.040));
  t.rows.push_back(axes_row("b-bbil", {{"algorithm", "alchemy"}, {"blur", "bilateral"}, {"samples", "16"}}, 30, 0.044));
  // Differs in two axes from every other row: must not be matched.
  t.rows.push_back(axes_row("c-bbil", {{"algorithm", "gtao"}, {"blur", "bilateral"}, {"samples", "32"}}, 99, 0.9));
  decide::mark_pareto(t);
  auto pairs = report::seed_pairs(t);
  auto blur = std::find_if(pairs.begin(), pairs.end(), [](const auto& p) { return p.axis == "blur"; });
  ASSERT_NE(blur, pairs.end());
  EXPECT_EQ(blur->pairs, 2);
  EXPECT_DOUBLE_EQ(blur->time_delta_pct, 35.0);  // median of +20 % and +50 %
  EXPECT_NEAR(blur->rmse_delta, 0.003, 1e-12);   // median of +0.002 and +0.004
  EXPECT_NE(blur->seed.find("§5.7"), std::string::npos);
  // a-bsep/b-bsep and a-bbil/b-bbil differ in the sample count alone.
  for (const auto& p : pairs) {
    if (p.axis != "blur") { EXPECT_EQ(p.pairs, p.axis == "samples" ? 2 : 0) << p.title; }
  }

  auto md = report::markdown_report(t);
  EXPECT_NE(md.find("| a-bsep | 10.00 | - | - | 0.0500"), std::string::npos) << md;  // on the front, no split
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

// The title says what the page is (a sweep, or a merge of tables; the ship report has its own test), and the
// cost-model diagnostics close the page as an appendix, after the evidence a decision rests on.
TEST(Report, TheTitleSaysWhatThePageIsAndTheCostModelsAreAnAppendix) {
  table::CostTable t;
  t.rows.push_back(axes_row("a-bsep", {{"algorithm", "alchemy"}, {"blur", "separable"}}, 10, 0.050));
  t.rows.push_back(axes_row("a-bbil", {{"algorithm", "alchemy"}, {"blur", "bilateral"}}, 12, 0.040));
  table::ModelFit model;
  model.scene = "s";
  model.view = "v";
  model.reason = "8 rows or fewer";
  t.meta.cost_models = std::vector<table::ModelFit>{model};
  const std::string md = report::markdown_report(t);
  EXPECT_EQ(md.rfind("# aovar sweep report\n", 0), 0u) << md.substr(0, 80);
  const auto appendix = md.find("## Appendix: cost-model diagnostics");
  ASSERT_NE(appendix, std::string::npos) << md;
  EXPECT_GT(appendix, md.find("## The pairs the seeds compared"));
  EXPECT_NE(md.find("- s / v: not predictive (8 rows or fewer)", appendix), std::string::npos);

  TempDir dir;
  report::write_reports(t, dir.path());
  const std::string html = util::read_file(dir / "report.html").value();
  EXPECT_NE(html.find("<title>aovar sweep report</title>"), std::string::npos);
  EXPECT_GT(html.find("Appendix: cost-model diagnostics"), html.find("The pairs the seeds compared"));

  t.meta.merged_from = std::vector<std::string>{"a/cost_table.json", "b/cost_table.json"};
  EXPECT_EQ(report::markdown_report(t).rfind("# aovar report of merged cost tables\n", 0), 0u);
}

// The split of each time (issue 55): the front tables give the variant's own part and its format's G-buffer
// next to the frame time that decides, the bars draw the G-buffer's part in grey, and a row without a
// measured split (predicted, or a table from before it) says "-".
TEST(Report, ShowsEachTimeSplitIntoOwnPassesAndTheGbuffer) {
  table::CostTable t;
  auto split = axes_row("alchemy-split", {{"algorithm", "alchemy"}}, 10, 0.05);
  split.time_ms.median = 12;
  split.gbuffer_ms = util::TimeStats{3, 4.8, 6, 3};
  t.rows = {split, axes_row("gtao-whole", {{"algorithm", "gtao"}}, 20, 0.04)};
  const auto parts = table::time_split(split);
  ASSERT_TRUE(parts);
  const std::string own = fmt::format("{:.2f}", parts->own), gbuffer = fmt::format("{:.2f}", parts->gbuffer);
  const std::string md = report::markdown_report(t);
  EXPECT_NE(md.find("| variant | paired ms [95 % interval] | own ms | G-buffer ms | rmse | ssim |"), std::string::npos) << md;
  EXPECT_NE(md.find("| alchemy-split | 10.00 | " + own + " | " + gbuffer + " | 0.0500"), std::string::npos) << md;
  EXPECT_NE(md.find("| gtao-whole | 20.00 | - | - | 0.0400"), std::string::npos) << md;
  EXPECT_NE(md.find("no measured split"), std::string::npos) << "the note says which rows have none";
  const std::string html = report::html_report(t, ".");
  EXPECT_NE(html.find("<th>own ms</th><th>G-buffer ms</th>"), std::string::npos);
  EXPECT_NE(html.find("<td>" + own + "</td><td>" + gbuffer + "</td>"), std::string::npos);
  EXPECT_NE(html.find("own " + own + " ms + G-buffer " + gbuffer + " ms"), std::string::npos) << "the bar's title";
  EXPECT_NE(html.find("the format's G-buffer " + gbuffer + " ms"), std::string::npos) << "its grey part";
}

// "Where the error comes from": per view, the front rows' breakdowns with their numbers and one reading
// generated from them (here both rows mostly far and too light); dominated rows and rows without a
// breakdown are left out, and a table without any has no section.
TEST(Report, WhereTheErrorComesFromPerView) {
  auto breakdown = [](double far_share, double light_mean) {
    metrics::ErrorBreakdown b;
    b.edge_band_px = 7.5;
    b.split_depth = 2;
    b.edge = {0.2, 0.05, 0.1, 0.01};
    b.interior = {0.8, 0.09, 0.9, 0.04};
    b.near = {0.5, 0.04, 1 - far_share, 0.01};
    b.far = {0.5, 0.12, far_share, 0.06};
    b.light = {0.7, 0.1, 0.9, light_mean};
    b.dark = {0.3, 0.03, 0.1, -0.02};
    return b;
  };
  table::CostTable t;
  t.rows.push_back(axes_row("alchemy-fast", {{"algorithm", "alchemy"}}, 10, 0.10));
  t.rows.push_back(axes_row("gtao-good", {{"algorithm", "gtao"}}, 20, 0.05));
  t.rows.push_back(axes_row("sao-bad", {{"algorithm", "sao"}}, 30, 0.20));  // dominated
  t.rows[0].error->breakdown = breakdown(0.7, 0.08);
  t.rows[1].error->breakdown = breakdown(0.9, 0.04);
  t.rows[2].error->breakdown = breakdown(0.1, 0.5);
  decide::mark_pareto(t);
  const std::string md = report::markdown_report(t);
  EXPECT_NE(md.find("### Where the error comes from"), std::string::npos) << md;
  EXPECT_NE(md.find("| alchemy-fast | 0.1000 | 7.5 | 10 % / 20 % | 0.0500 | 0.0900 | 30 % (0.0400) | 70 % (0.1200) | "
                    "90 % (+0.0800) | 10 % (-0.0200) |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| gtao-good | 0.0500 | 7.5 | 10 % / 20 % |"), std::string::npos) << md;
  EXPECT_EQ(md.find("| sao-bad | 0.2000"), std::string::npos) << "not on the front";
  // The reading: the mean of the two rows (far 80 %, light 90 % with mean +0.060, edge 10 % on 20 %).
  EXPECT_NE(md.find("Reading (mean over the 2 rows): spread over the interior, not the screen edges (the edge band "
                    "holds 10 % of the error on 20 % of the pixels); mostly in the far half (80 %); mostly too light "
                    "(90 %, mean +0.060): occluders missed."),
            std::string::npos)
      << md;
  TempDir dir;
  report::write_reports(t, dir.path());
  const auto html = util::read_file(dir / "report.html").value();
  EXPECT_NE(html.find("<h3>Where the error comes from</h3>"), std::string::npos);
  EXPECT_NE(html.find("<td>70 % (0.1200)</td>"), std::string::npos);
  EXPECT_NE(html.find("mostly in the far half (80 %)"), std::string::npos);

  for (auto& r : t.rows) r.error->breakdown.reset();  // a table measured before the breakdown
  EXPECT_EQ(report::markdown_report(t).find("Where the error comes from"), std::string::npos);
}

// `aovar report --table`: the reports of a table written elsewhere (a merged or edited one), the worst-view
// front across two views, predicted rows marked; a missing table is a one-line error naming it.
TEST(Report, CliWritesReportsFromATable) {
  table::CostTable t;
  auto add = [&](const std::string& v, const std::string& view, double ms, double rmse) {
    auto r = axes_row(v, {{"algorithm", v.substr(0, v.find('-'))}}, ms, rmse);
    r.view = view;
    t.rows.push_back(r);
  };
  add("alchemy-fast", "a", 10, 0.10), add("alchemy-fast", "b", 11, 0.12);
  add("gtao-good", "a", 20, 0.05), add("gtao-good", "b", 22, 0.06);
  add("sao-bad", "a", 30, 0.20), add("sao-bad", "b", 31, 0.21);  // dominated on both views
  auto predicted = axes_row("hbao-guess", {{"algorithm", "hbao"}}, 15, 0);
  predicted.error.reset();
  predicted.predicted = true;
  predicted.time_ms.n = 0;
  t.rows.push_back(predicted);
  decide::mark_pareto(t);
  TempDir dir;
  table::write_json(t, dir / "in" / "cost_table.json");
  auto r = run_aovar("report --table " + (dir / "in" / "cost_table.json").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("7 rows"), std::string::npos) << r.output;
  auto md = util::read_file(dir / "out" / "report.md").value();
  EXPECT_NE(md.find("The front over the worst view: s / lavapipe"), std::string::npos) << md;
  EXPECT_NE(md.find("| gtao-good | 22.00 | 0.0600"), std::string::npos) << "worst of the two views:\n" << md;
  EXPECT_EQ(md.find("| sao-bad |"), std::string::npos) << md;
  auto html = util::read_file(dir / "out" / "report.html").value();
  EXPECT_NE(html.find("hbao-guess 15.00 ms (predicted)"), std::string::npos) << "predicted bars are labelled";
  EXPECT_FALSE(std::filesystem::exists(dir / "in" / "report.md")) << "--out decides where reports go";

  auto missing = run_aovar("report --table " + (dir / "nope.json").string());
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("nope.json"), std::string::npos) << missing.output;
}

// A headless Chromium screenshot of report.html shows the charts: marks in the manifest's colours of two
// methods (scatter points, legend, time bars) and dark text, axes and the front line. An HTML whose SVG
// failed to parse would show none of the colours.
TEST(Report, HtmlRendersInHeadlessChromium) {
  const auto manifest = variants::load_manifest(source_dir() / "shader_src/aovar.toml");
  const auto& methods = manifest.axis_values(variants::Axis::algorithm);
  ASSERT_GE(methods.size(), 2u);
  const variants::Algorithm* drawn[2] = {manifest.algorithm(methods[0].text), manifest.algorithm(methods[1].text)};
  table::CostTable t;
  for (int i = 0; i < 12; ++i) {
    const std::string alg = drawn[i % 2]->name;
    t.rows.push_back(axes_row(alg + "-" + std::to_string(i), {{"algorithm", alg}, {"samples", std::to_string(4 + i)}},
                         10 + 2 * i, 0.1 - 0.005 * i + 0.01 * (i % 3)));
  }
  decide::mark_pareto(t);
  TempDir dir;
  report::write_reports(t, dir.path(), manifest.algorithms);
  std::string cmd = "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" +
                    (dir / "profile").string() + " --window-size=1000,900 --screenshot=" + (dir / "shot.png").string() +
                    " file://" + (dir / "report.html").string() + " >" + (dir / "chromium.log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "chromium failed (installed by scripts/deps): " << cmd;
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load((dir / "shot.png").c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr) << "no screenshot";
  EXPECT_EQ(w, 1000);
  auto channel = [](const std::string& hex, int i) { return std::stoi(hex.substr(1 + 2 * i, 2), nullptr, 16); };
  long marks[2] = {0, 0}, dark = 0;
  for (long i = 0; i < long(w) * h; ++i) {
    int r = px[3 * i], g = px[3 * i + 1], b = px[3 * i + 2];
    for (int k = 0; k < 2; ++k) {
      const std::string& c = drawn[k]->color;
      marks[k] += std::abs(r - channel(c, 0)) + std::abs(g - channel(c, 1)) + std::abs(b - channel(c, 2)) < 60;
    }
    dark += r < 60 && g < 60 && b < 60;
  }
  stbi_image_free(px);
  for (int k = 0; k < 2; ++k) EXPECT_GT(marks[k], 50) << drawn[k]->name << "'s points are drawn in " << drawn[k]->color;
  EXPECT_GT(dark, 500) << "text, axes and the front line are drawn";
}

// The HTML colours each method as the manifest says, and names it with its display name in the legend; a
// method the manifest lacks is grey.
TEST(Report, MethodColoursComeFromTheManifest) {
  const auto manifest = variants::parse_manifest(R"(
[axes]
algorithm = ["first", "second"]
samples = [8]
progressive = [false]
normals = ["rgb8"]
position = ["depth"]
reconstruct = ["similar_triangles"]
depth_format = ["r32f"]
blur = ["none"]
resolution = [1.0]
precision = ["highp"]
[passes.ao]
vertex = { template = "v.vert" }
fragment = { template = "f.frag" }
[algorithms.first]
color = "#123abc"
display_name = "First AO"
[algorithms.second]
)", "m.toml");
  table::CostTable t;
  t.rows.push_back(axes_row("first-a", {{"algorithm", "first"}}, 10, 0.1));
  t.rows.push_back(axes_row("second-a", {{"algorithm", "second"}}, 12, 0.05));
  t.rows.push_back(axes_row("stranger-a", {{"algorithm", "stranger"}}, 14, 0.01));
  const std::string html = report::html_report(t, ".", manifest.algorithms);
  EXPECT_TRUE(has_text(html, "<span style=\"color:#123abc\">&#9679;</span> first (First AO)")) << html;
  const std::string second = manifest.algorithm("second")->color;
  EXPECT_EQ(second, variants::method_palette_color(1)) << "no colour: the palette's at its place";
  EXPECT_TRUE(has_text(html, "<span style=\"color:" + second + "\">&#9679;</span> second &nbsp;")) << html;
  EXPECT_TRUE(has_text(html, "<span style=\"color:#7f7f7f\">&#9679;</span> stranger &nbsp;")) << html;
}

}  // namespace
}  // namespace aovar::test
