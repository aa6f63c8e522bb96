// Measurement reuse (issue 8): a row is measured again exactly when one of its inputs changes — the
// variant's programs, the scene's content, the view's camera, the backend, size, threads, reps, warm-up,
// radius, the calibrated parameters, the reference settings — and never because the selection or --batch
// changed; a repeated sweep measures, traces and composes nothing; --prune-dominated skips what the cost model
// predicts to be dominated and measures a sample of it anyway (and prunes nothing when no model is predictive).
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "measure/measure.h"
#include "model_verdicts.h"
#include "table/table.h"
#include "render_support.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

namespace fs = std::filesystem;
using Rows = std::set<std::string>;

const std::string kBase = "alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp";
const std::string kAlchemy8 = "alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp";
const std::string kGtao = "gtao-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp";

// "variant view backend" of the rows a run measured (not reused).
Rows measured(const measure::MeasureResult& r) {
  Rows out;
  for (const auto& row : r.rows)
    if (!row.reused) out.insert(row.variant + " " + row.view + " " + row.backend);
  return out;
}

Rows rows(const std::vector<std::string>& variants, const std::vector<std::string>& views,
          const std::vector<std::string>& backends = {"lavapipe"}) {
  Rows out;
  for (const auto& v : variants)
    for (const auto& view : views)
      for (const auto& b : backends) out.insert(v + " " + view + " " + b);
  return out;
}

// Two views of builtin:stairs from a side file, the first one's eye given.
void write_views(const fs::path& file, const std::string& eye_a) {
  util::write_atomic(file, "[[view]]\nname = \"a\"\neye = [" + eye_a + "]\ntarget = [-1.0, 0.8, 0.8]\n\n"
                           "[[view]]\nname = \"b\"\neye = [2.6, 0.8, 3.6]\ntarget = [0.9, 0.15, 2.3]\n");
}

measure::MeasureOptions tiny(const TempDir& dir) { return tiny_measure(dir.path(), {kBase, kAlchemy8, kGtao}, kBase); }

TEST(Reuse, SelectionViewCalibrationAndReferenceReMeasureOnlyTheirRows) {
  TempDir dir;
  auto o = tiny(dir);
  write_views(dir / "views.toml", "4.5, 2.8, 6.5");
  o.views_file = dir / "views.toml";
  o.views = {"a", "b"};
  o.truth.enabled = true;
  o.truth.rays = 8;
  const std::vector<std::string> all = {kBase, kAlchemy8, kGtao};
  EXPECT_EQ(measured(measure::run_measure(o)), rows(all, {"a", "b"}));
  EXPECT_EQ(measured(measure::run_measure(o)), Rows{}) << "unchanged inputs";

  // The selection and the batch size are not inputs: a narrower run, then the full one again, then another
  // batch size measure nothing (rows a run does not select stay in measure.json as kept_rows).
  o.globs = {kBase, kAlchemy8};
  auto narrow = measure::run_measure(o);
  EXPECT_EQ(measured(narrow), Rows{});
  EXPECT_EQ(narrow.rows.size(), 4u);
  EXPECT_EQ(narrow.kept_rows.size(), 2u) << "gtao's rows, kept for a later run";
  o.globs = all;
  EXPECT_EQ(measured(measure::run_measure(o)), Rows{}) << "gtao's rows came back from kept_rows";
  o.timing.batch = 2;
  EXPECT_EQ(measured(measure::run_measure(o)), Rows{});

  // A calibrated value of one algorithm: its rows, and the baseline's (timed in the same rounds).
  o.calibration.values["gtao"]["ao.falloff"] = 0.3;
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kGtao, kBase}, {"a", "b"}));

  // One view's camera (the name stays): that view's rows only.
  write_views(dir / "views.toml", "4.5, 2.9, 6.5");
  EXPECT_EQ(measured(measure::run_measure(o)), rows(all, {"a"}));

  // The reference (rays here; radius, size and the camera are in its key too): every row's error.
  o.truth.rays = 16;
  EXPECT_EQ(measured(measure::run_measure(o)), rows(all, {"a", "b"}));
  EXPECT_EQ(measured(measure::run_measure(o)), Rows{});
}

TEST(Reuse, EachRenderSettingAndBackendReMeasures) {
  TempDir dir;
  auto o = tiny(dir);
  const auto all = rows({kBase, kAlchemy8, kGtao}, {"overview"});
  EXPECT_EQ(measured(measure::run_measure(o)), all);
  o.size = {64, 40};
  EXPECT_EQ(measured(measure::run_measure(o)), all) << "size";
  o.scope.threads = 1;
  EXPECT_EQ(measured(measure::run_measure(o)), all) << "threads";
  o.timing.reps = 2;
  EXPECT_EQ(measured(measure::run_measure(o)), all) << "reps";
  o.timing.warmup = 1;
  EXPECT_EQ(measured(measure::run_measure(o)), all) << "warmup";
  o.radius = 0.3f;
  EXPECT_EQ(measured(measure::run_measure(o)), all) << "radius";
  o.params["ao.falloff"] = 0.5;
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kBase, kGtao}, {"overview"})) << "a --param gtao takes";
  o.backends = {"lavapipe", "osmesa"};
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kBase, kAlchemy8, kGtao}, {"overview"}, {"osmesa"}))
      << "another backend measures its own rows only";
  EXPECT_EQ(measured(measure::run_measure(o)), Rows{});
}

TEST(Reuse, ProgramAndSceneContentReMeasure) {
  TempDir dir;
  auto o = tiny(dir);
  o.scope.manifest = copy_shader_src(dir);
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kBase, kAlchemy8, kGtao}, {"overview"}));
  // A template's bytes change gtao's programs: its row, and the baseline timed with it.
  append_line(dir / "shader_src" / "ao" / "gtao.glsl", "// changes the program hash, not the code");
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kBase, kGtao}, {"overview"}));
  o.globs = {kBase, kAlchemy8};
  o.out = dir / "obj";
  // A scene file whose content changes under the same name: every row.
  const fs::path obj = dir / "box.obj";
  auto write_obj = [&](const std::string& top) {
    util::write_atomic(obj, "v -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\nv -1 0 -1\nv 1 0 -1\nv 1 " + top +
                                " -1\nv -1 " + top + " -1\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n");
  };
  write_obj("2");
  o.scene = obj.string();
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kBase, kAlchemy8}, {"overview"}));
  EXPECT_EQ(measured(measure::run_measure(o)), Rows{});
  write_obj("2.5");
  EXPECT_EQ(measured(measure::run_measure(o)), rows({kBase, kAlchemy8}, {"overview"}));
}

// --no-prune: at 96x54 the stairs' profile drops quarter resolution, whose row this test needs.
std::string sweep_args(const fs::path& out) {
  return "sweep --scene builtin:stairs --view overview --size 96x54 --reps 2 --rays 16 --no-prune"
         " --variants 'alchemy-s0[48]-p0-nrgb8-zdep-rst-d32-bsep-x[124]-hp' --out " + out.string();
}

TEST(Reuse, ARepeatedSweepMeasuresNothingNew) {
  TempDir dir;
  const fs::path out = dir / "sweep";
  auto first = run_aovar(sweep_args(out));
  ASSERT_EQ(first.status, 0) << first.output;
  EXPECT_NE(first.output.find("(6 measured, 0 reused"), std::string::npos) << first.output;
  auto table = util::read_file(out / "cost_table.json").value();
  auto stamp = [&](const char* f) { return fs::last_write_time(out / f); };
  const auto sheet = stamp("measure/builtin_stairs/contact_sheet-lavapipe-overview.png");

  auto second = run_aovar(sweep_args(out));
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_NE(second.output.find("(0 measured, 6 reused"), std::string::npos) << second.output;
  EXPECT_EQ(util::read_file(out / "cost_table.json").value(), table) << "every row reused exactly";
  EXPECT_EQ(stamp("measure/builtin_stairs/contact_sheet-lavapipe-overview.png"), sheet)
      << "the sheets already show these rows: not composed again";
  auto m = nlohmann::json::parse(util::read_file(out / "measure/builtin_stairs/measure.json").value());
  EXPECT_TRUE(m.at("runs").empty());

  // x2 and x4 run the same programs into different textures: each keeps its own row (their inputs once
  // collided, so a re-run gave x4 the x2 row).
  auto t = table::read_table(out / "cost_table.json");
  std::map<std::string, double> rmse;
  for (const auto& row : t.rows) rmse[row.variant] = row.error->rmse;
  EXPECT_NE(rmse.at("alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x2-hp"), rmse.at("alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x4-hp"));
}

// --prune-dominated whose seed-phase models are not predictive: a note per such group, nothing predicted
// dominated or skipped, every candidate measured.
void expect_nothing_pruned(const std::string& output, const table::CostTable& t, const std::set<std::string>& refused) {
  for (const auto& g : refused)
    EXPECT_NE(output.find("note: --prune-dominated: no predictive cost model for " + g + " ("), std::string::npos) << output;
  const auto& scene = t.meta.prune.at("scenes").at(0);
  EXPECT_EQ(scene.at("predicted_dominated"), 0) << scene.dump(1);
  EXPECT_EQ(t.meta.prune.at("skipped"), 0);
  std::set<std::string> in_table;
  for (const auto& row : t.rows) in_table.insert(row.variant);
  EXPECT_EQ(in_table.size(), 26u) << "every candidate measured";
  EXPECT_NE(output.find("# prune: 0 variants skipped"), std::string::npos) << output;
}

// Unsharp masking is clearly worse than Alchemy on the atrium (RMSE about 0.12 against 0.07-0.10) and no
// faster: most of its variants are dominated by Alchemy's fastest.
TEST(Reuse, PruneDominatedSkipsPredictedDominatedVariantsAndChecksASample) {
  TempDir dir;
  const fs::path out = dir / "sweep";
  const std::string args = "sweep --scene builtin:atrium --view overview --size 128x72 --reps 2 --rays 16"
                           " --variants 'unsharp-s*-p0-ndep-zdep-_r-d16-b*-x1-hp'"
                           " --variants 'alchemy-s0[48]-p0-nrg8-zdep-rst-d16-b*-x[12]-hp' --out " + out.string();
  auto pruned = run_aovar(args + " --prune-dominated --prune-check 1");
  ASSERT_EQ(pruned.status, 0) << pruned.output;
  EXPECT_NE(pruned.output.find("# prune: "), std::string::npos) << pruned.output;
  auto t = table::read_table(out / "cost_table.json");
  const auto& prune = t.meta.prune;
  const auto& scene = prune.at("scenes").at(0);
  // The seed phase's models decide (8 rows of 128x72 timings may be noise): with none predictive, no pruning.
  if (const auto refused = unpredictable_groups(scene.at("cost_models")); !refused.empty())
    return expect_nothing_pruned(pruned.output, t, refused);
  const int skipped = prune.at("skipped");
  EXPECT_GT(skipped, 0) << scene.dump(1);
  EXPECT_EQ(scene.at("skipped_variants").size(), static_cast<std::size_t>(skipped));
  EXPECT_EQ(scene.at("candidates"), 26);
  std::set<std::string> in_table;
  for (const auto& row : t.rows) in_table.insert(row.variant);
  EXPECT_EQ(in_table.size() + skipped, 26u);
  for (const auto& v : scene.at("skipped_variants")) EXPECT_FALSE(in_table.count(v)) << v << " was skipped, yet has a measured row";
  // The check sample: max(--prune-check, a tenth) of the dominated ones, measured and reported.
  ASSERT_GE(scene.at("checked").size(), 1u);
  EXPECT_EQ(prune.at("checked"), scene.at("checked").size());
  for (const auto& v : scene.at("checked")) EXPECT_TRUE(in_table.count(v)) << v << " was checked: it has rows";
  EXPECT_EQ(prune.at("checked_on_front"), scene.at("checked_on_front").size());
  EXPECT_NE(pruned.output.find(fmt::format("{} more measured anyway as a check, {} of them on the Pareto front",
                                           scene.at("checked").size(), scene.at("checked_on_front").size())),
            std::string::npos) << pruned.output;

  // Repeated, the same rows decide the same: nothing is measured. Without pruning, only the skipped variants
  // are (and the baseline, timed with them): the seeds' and the others' rows were kept.
  auto again = run_aovar(args + " --prune-dominated --prune-check 1");
  EXPECT_NE(again.output.find("(0 measured"), std::string::npos) << again.output;
  auto full = run_aovar(args);
  EXPECT_NE(full.output.find(fmt::format("26 rows ({} measured", skipped + 1)), std::string::npos) << full.output;
}

// Inputs hash: a fixed count, auto, and auto with another target are different measurements.
TEST(Reuse, RepsAutoAndItsTargetAreInputs) {
  TempDir dir;
  auto o = tiny_measure(dir.path(), {"alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp"}, "alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp");
  o.images = false;
  o.timing.reps = 10;
  auto fresh = [&] {
    int n = 0;
    for (const auto& row : measure::run_measure(o).rows) n += row.reused ? 0 : 1;
    return n;
  };
  EXPECT_EQ(fresh(), 2);
  o.timing.auto_reps = measure::AutoReps{0.05, 0.2, 200};
  EXPECT_EQ(fresh(), 2) << "auto after a fixed 10";
  EXPECT_EQ(fresh(), 0) << "the same auto";
  o.timing.auto_reps->ci_target = 0.03;
  EXPECT_EQ(fresh(), 2) << "another target";
  o.timing.auto_reps.reset();
  EXPECT_EQ(fresh(), 2) << "back to a fixed 10 (the earlier fixed rows were replaced)";
}

}  // namespace
}  // namespace aovar::test
