// What the CLI prints, formatted by the libraries: compile (list, generate), analyze, reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "analyze/text.h"
#include "compile/text.h"
#include "reference/text.h"

namespace {
using namespace aovar;

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// Three variants (the third the same programs as the first), one dropped by a rule on line 12, one target.
compile::CompiledSpace small_space() {
  compile::CompiledSpace c;
  c.manifest.path = "shader_src/aovar.toml";
  variants::Rule rule;
  rule.reason = "progressive needs a history buffer";
  rule.pos.line = 12;
  c.manifest.rules.push_back(rule);
  c.space.space = 8;
  c.space.collapsed = 3;
  for (const char* key : {"alchemy-s08-a", "alchemy-s16-b", "sao-s08-c"}) c.space.variants.push_back({key, {}, {}});
  c.space.pruned.push_back({"alchemy-s08-p1-x", 0});
  c.variant_same_as = {-1, -1, 0};
  c.dedup = 2;
  c.targets = {variants::Target::vulkan};
  compile::TargetStats st;
  st.programs = 6;
  st.unique = 4;
  st.compiled = 3;
  st.cached = 1;
  st.failed = 0;
  st.spirv_bytes = 12345;
  c.stats = {st};
  return c;
}

TEST(CliText, ListNamesEachVariantItsDuplicateAndTheCounts) {
  auto c = small_space();
  EXPECT_EQ(compile::list_text(c, false),
            "alchemy-s08-a\nalchemy-s16-b\nsao-s08-c  same as alchemy-s08-a\n# space 8 / rules 3 / dedup 2\n");
}

TEST(CliText, ListPrunedAddsEachRuleDropWithReasonAndManifestLine) {
  auto c = small_space();
  std::string text = compile::list_text(c, true);
  EXPECT_NE(text.find("alchemy-s08-p1-x  dropped: progressive needs a history buffer (shader_src/aovar.toml:12)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text, compile::list_text(c, false).insert(text.find("alchemy-s08-p1-x"),
                                                       compile::rule_drops_text(c.manifest, c.space)));
  EXPECT_EQ(count_lines(text), 5);
}

TEST(CliText, SummaryTableHasOneRowPerTargetAndTheCountsLine) {
  auto c = small_space();
  std::string table = compile::summary_table(c);
  EXPECT_EQ(count_lines(table), 3) << table;
  EXPECT_EQ(table.rfind("target ", 0), 0u) << table;
  EXPECT_NE(table.find("vulkan           6       4         3       1       0        12345\n"), std::string::npos)
      << table;
  EXPECT_NE(table.find("space 8 / rules 3 / dedup 2  (3 variants)\n"), std::string::npos) << table;
  // A no-op generate prints the counts part of the recorded table.
  std::string noop = compile::up_to_date_text(table, "out", 0.25);
  EXPECT_EQ(noop, "space 8 / rules 3 / dedup 2  (3 variants)\n"
                  "up to date: nothing compiled, no file written -> out (0.25 s)\n");
}

TEST(CliText, FailureLineCountsErrorsAndFailedBuilds) {
  auto c = small_space();
  c.errors = 2;
  c.stats[0].failed = 3;
  EXPECT_EQ(compile::failure_line(c), "aovar: 2 error(s), 3 program build(s) failed; nothing was written\n");
}

TEST(CliText, StaleTextListsTwentyFilesAndTheCommandToRun) {
  compile::OutputReport r;
  EXPECT_EQ(compile::stale_text(r, "gen"), "");
  for (int i = 0; i < 23; ++i) r.changed.push_back("gen/f" + std::to_string(i));
  std::string text = compile::stale_text(r, "gen");
  EXPECT_EQ(count_lines(text), 22) << text;
  EXPECT_NE(text.find("stale: gen/f19\n"), std::string::npos);
  EXPECT_EQ(text.find("stale: gen/f20\n"), std::string::npos);
  EXPECT_NE(text.find("stale: ... and 3 more\n"), std::string::npos);
  EXPECT_NE(text.find("aovar: 23 generated file(s) in gen are out of date: run aovar generate --out gen\n"),
            std::string::npos);
  r.unchanged = 7;
  r.written = 2;
  r.removed = 1;
  EXPECT_EQ(compile::up_to_date_line(r, "gen"), "7 files up to date in gen\n");
  EXPECT_EQ(compile::written_line(r, "gen", 1.5), "files: 2 written, 7 unchanged, 1 removed -> gen (1.50 s)\n");
}

TEST(CliText, AnalyzeSummaryCountsProgramsAndVariants) {
  analyze::Analysis a;
  a.programs.resize(5);
  a.variants.resize(2);
  EXPECT_EQ(analyze::summary_line(a, "gen/analysis.json"),
            "# 5 programs, 2 variants (counts per pixel, upper bounds) -> gen/analysis.json\n");
}

TEST(CliText, ReferenceTableHasEachViewItsFiguresAndTheScene) {
  reference::RunResult r;
  r.scene = "builtin:atrium";
  r.triangles = 1234;
  r.wall_s = 2.5;
  reference::RunView v;
  v.view = "overview";
  v.options.size = {64, 32};
  v.options.rays = 16;
  v.options.radius = 0.5f;
  v.stats.mean_visibility = 0.75;
  v.stats.mean_std_error = 0.0125;
  v.stats.background_share = 0.1;
  v.trace_s = 2;
  v.rays_traced = 4'000'000;
  r.views.push_back(v);
  v.view = "closeup";
  v.from_cache = true;
  v.trace_s = 0;
  r.views.push_back(v);
  std::string text = reference::to_text(r, "refs");
  EXPECT_EQ(count_lines(text), 4) << text;
  EXPECT_EQ(text.rfind("view ", 0), 0u) << text;
  // size, rays, mode, radius, mean visibility, mean error, background %, trace s, Mrays/s
  EXPECT_NE(text.find("overview         64x32     16 occlusion       0.5    0.7500    0.0125    10.0      2.00     2.00\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("closeup "), std::string::npos);
  EXPECT_NE(text.find("0.00  (cached)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# scene builtin:atrium (1234 triangles) in 2.5 s -> refs/reference.json\n"), std::string::npos)
      << text;
}

}  // namespace

// ---- the results of measure, sweep, stress, calibrate and profile ----
#include "calibrate/text.h"
#include "measure/text.h"
#include "profile/pruned_text.h"
#include "stress/text.h"
#include "sweep/text.h"

namespace {

measure::MeasureRow measured_row(const char* variant, double min_ms, bool baseline) {
  measure::MeasureRow r;
  r.variant = variant;
  r.backend = "lavapipe";
  r.view = "overview";
  r.time_ms = {min_ms, min_ms + 1, min_ms + 2, 10};
  r.rel_time = min_ms / 2;
  r.passes = {{"gbuffer", {0.5, 0.6, 0.7, 10}}, {"ao", {min_ms - 0.5, 0, 0, 10}}};
  r.is_baseline = baseline;
  return r;
}

TEST(CliText, MeasureTableListsEveryRowWithItsTimesAndErrorColumnsOnlyWithAReference) {
  measure::MeasureResult r;
  r.rows = {measured_row("alchemy-s08-x", 2.0, true), measured_row("alchemy-s16-x", 3.25, false)};
  std::string plain = measure::to_text(r);
  EXPECT_EQ(count_lines(plain), 3);
  EXPECT_EQ(plain.find("rmse"), std::string::npos);
  EXPECT_NE(plain.find("alchemy-s16-x"), std::string::npos);
  EXPECT_NE(plain.find("3.25"), std::string::npos);
  EXPECT_NE(plain.find("ao 2.75"), std::string::npos) << plain;
  EXPECT_NE(plain.find("(baseline)"), std::string::npos);
  metrics::ErrorStats e;
  e.rmse = 0.0625;
  e.ssim = 0.875;
  r.rows[1].error = e;
  std::string truth = measure::to_text(r);
  EXPECT_NE(truth.find("rmse"), std::string::npos);
  EXPECT_NE(truth.find("0.0625  0.8750"), std::string::npos) << truth;
  EXPECT_NE(truth.find("             -"), std::string::npos) << "the row without an error gets a dash";
  EXPECT_EQ(measure::where_text(r), "") << "no breakdown, no section";
  metrics::ErrorBreakdown b;  // mostly far and too light
  b.edge_band_px = 4;
  b.edge = {0.25, 0.05, 0.25, 0.01};
  b.interior = {0.75, 0.06, 0.75, 0.02};
  b.near = {0.5, 0.03, 0.2, 0.0};
  b.far = {0.5, 0.08, 0.8, 0.04};
  b.light = {0.6, 0.07, 0.9, 0.05};
  b.dark = {0.4, 0.02, 0.1, -0.01};
  r.rows[1].error->breakdown = b;
  const std::string where = measure::where_text(r);
  EXPECT_NE(where.find("where the error comes from:\n  alchemy-s16-x lavapipe overview: edge band 4.0 px: 25 % of the "
                       "error on 25 % of the pixels"),
            std::string::npos)
      << where;
  EXPECT_NE(where.find("mostly in the far half (80 %); mostly too light (90 %, mean +0.050): occluders missed"),
            std::string::npos)
      << where;
  EXPECT_NE(measure::to_text(r).find(where), std::string::npos) << "measure prints it after the table";
}

TEST(CliText, MeasureNotesNameTheSceneTheCountsAndWhereTheyWentOnlyWithAnOutputFolder) {
  measure::MeasureResult r;
  r.scene = "builtin:atrium";
  r.triangles = 1234;
  r.radius = 0.5f;
  r.counts = "space 8 / rules 3";
  r.rows = {measured_row("a", 1, false)};
  render::DeviceInfo device;
  device.backend = "lavapipe", device.device = "llvmpipe", device.api_version = "Vulkan 1.3", device.driver = "Mesa";
  device.threads = 2, device.timing = "timestamp queries";
  r.devices = {device};
  measure::MeasureOptions o;
  o.size = {64, 36};
  std::string no_out = measure::notes_text(r, o, {});
  EXPECT_NE(no_out.find("# lavapipe: llvmpipe, Vulkan 1.3, 2 threads"), std::string::npos) << no_out;
  EXPECT_NE(no_out.find("scene builtin:atrium (1234 triangles), radius 0.5"), std::string::npos) << no_out;
  EXPECT_NE(no_out.find("at 64x36"), std::string::npos);
  EXPECT_EQ(no_out.find("->"), std::string::npos);
  EXPECT_EQ(no_out.find("calibrated"), std::string::npos);
  o.out = "/tmp/somewhere";
  o.calibration.values["alchemy"]["ao.intensity"] = 1.5;
  std::string with_out = measure::notes_text(r, o, "shader_src/calibration.json");
  EXPECT_NE(with_out.find("-> /tmp/somewhere/measure.json"), std::string::npos) << with_out;
  EXPECT_NE(with_out.find("# calibrated parameters: shader_src/calibration.json"), std::string::npos) << with_out;
}

TEST(CliText, SweepNotesReportTheCostModelsTheCountsAndTheReport) {
  sweep::SweepResult r;
  sweep::ModelFit fit;
  fit.scene = "s";
  fit.view = "v";
  fit.backend = "lavapipe";
  fit.rows = 9;
  fit.cv_r2 = 0.5;
  fit.cv_spearman = 0.75;
  fit.cv_spearman_min = 0.625;
  fit.features = "compact static";
  fit.predictive = true;  // the not predictive form: test_cost_models.cpp
  fit.predicts = true;
  r.cost_models = {fit};
  r.rows_measured = 9;
  sweep::SweepOptions o;
  o.out = "/tmp/sw";
  std::string s = sweep::notes_text(r, o, {});
  EXPECT_NE(s.find("# cost model s v lavapipe: 9 rows, cross-validated R2 0.500, Spearman 0.750 (against time_ms.min "
                   "0.625; compact static features), predicts"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("(9 measured, 0 reused, 0 predicted)"), std::string::npos) << s;
  EXPECT_NE(s.find("# report: /tmp/sw/report.html"), std::string::npos) << s;
  EXPECT_EQ(s.find("calibrated by"), std::string::npos);
  EXPECT_NE(sweep::notes_text(r, o, "cal.json").find(", calibrated by cal.json"), std::string::npos);
}

TEST(CliText, StressTextListsOnlyFailedVariantsWithTheirReproducers) {
  stress::Result r;
  stress::Check ok, bad;
  ok.variant = bad.variant = "alchemy-s08-x";
  ok.case_name = "open-plane";
  bad.case_name = "grazing";
  ok.backend = bad.backend = "lavapipe";
  bad.failure = "12 NaN";
  r.checks = {ok, bad};
  stress::VariantReport failed, passed;
  failed.variant = "alchemy-s08-x";
  failed.shipped = true;
  failed.failures = {1};
  passed.variant = "sao-s08-x";
  r.variants = {failed, passed};
  r.failed = r.shipped_failed = 1;
  stress::Options o;
  o.backends = {"lavapipe"};
  auto cases = stress::default_cases();
  std::string s = stress::to_text(r, o, cases);
  EXPECT_NE(s.find("FAIL alchemy-s08-x (shipped)\n  grazing (lavapipe): 12 NaN\n    reproduce: aovar stress"), std::string::npos) << s;
  EXPECT_EQ(s.find("sao-s08-x"), std::string::npos) << "a variant that passed is not listed";
  EXPECT_NE(s.find(fmt::format("# 2 variants x {} cases x 1 backends: 2 checks", cases.size())), std::string::npos) << s;
  std::string list = stress::cases_text(cases);
  EXPECT_EQ(count_lines(list), static_cast<int>(cases.size()));
  EXPECT_NE(list.find(cases.front().name), std::string::npos);
}

TEST(CliText, CalibrationTextShowsEachFitBeforeAndAfter) {
  calibrate::Calibration c;
  c.backend = "lavapipe";
  c.size = {320, 180};
  c.rays = 64;
  c.views.training = {{"builtin:stairs", "overview"}, {"builtin:stairs", "closeup"}};
  c.views.holdout = {{"builtin:stairs", "background"}};
  calibrate::Fit f;
  f.algorithm = "alchemy";
  f.budget = 100;
  f.search.evaluations = 42;
  f.search.method = "BOBYQA";
  f.search.converged = true;
  f.search.stop = "x tolerance";
  f.search.best_so_far = {0.04, 0.0225, 0.01, 0.01, 0.0025};
  f.train_rmse_before = 0.25;
  f.train_rmse_after = 0.125;
  f.holdout_rmse_before = 0.5;
  f.holdout_rmse_after = 0.375;
  f.fitted = {{"ao.intensity", 1.5}};
  f.defaults = {{"ao.intensity", 1.0}};
  c.fits = {f};
  std::string s = calibrate::to_text(c, "out/calibration.json");
  EXPECT_NE(s.find("alchemy       42 / 100  0.2500 -> 0.1250  0.5000 -> 0.3750  ao.intensity 1.5 (1)"), std::string::npos) << s;
  EXPECT_NE(s.find("BOBYQA converged (x tolerance); training error (root of the mean MSE) by evaluation: 1: 0.2000, 2: "
                   "0.1500, 3: 0.1000, 4: 0.1000, 5: 0.0500"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("# lavapipe at 320x180, references 64 rays"), std::string::npos) << s;
  EXPECT_NE(s.find("2 training and 1 held-out views of builtin:stairs; -> out/calibration.json"), std::string::npos) << s;
}

TEST(CliText, SceneListingKeepsKeysAndGivesReasonsOnlyWhenAsked) {
  variants::Manifest m;
  variants::VariantSpace space;
  space.space = 10;
  space.collapsed = 4;
  profile::Pruned p;
  p.kept = {"k1", "k2"};
  p.dropped = {{"d1", "depth_format r16f: 12 % of R"}};
  p.rules = {"depth_format r16f"};
  std::string short_list = profile::list_text(m, space, p, "builtin:far", false);
  EXPECT_EQ(short_list, "k1\nk2\n# space 10 / rules 4 / selected 3 / scene builtin:far keeps 2 (1 dropped, with reasons: --pruned)\n");
  std::string long_list = profile::list_text(m, space, p, "builtin:far", true);
  EXPECT_NE(long_list.find("d1  dropped for builtin:far: depth_format r16f: 12 % of R\n"), std::string::npos) << long_list;
  EXPECT_EQ(profile::prune_line(7, p, "builtin:far"),
            "# 7 variants after rules; the scene keeps 2 and drops 1 (aovar list --scene builtin:far --pruned)\n");
}

}  // namespace
