// Calibration: the bounded minimiser, fitting a method against ray-traced references (error falls on the
// training views, values stay in range), the calibration file, and `measure --reference` with a calibration.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "calibrate/calibrate.h"
#include "calibrate/file.h"
#include "calibrate/optimize.h"
#include "compile/generate.h"
#include "measure/measure.h"
#include "runner/variant_runner.h"
#include "variants/manifest.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

TEST(Calibrate, MinimizerFindsABowlsMinimumAndStaysInBounds) {
  auto bowl = [](const std::vector<double>& u) {
    return (u[0] - 0.3) * (u[0] - 0.3) + 2 * (u[1] - 0.7) * (u[1] - 0.7) + 0.5 * (u[0] - 0.3) * (u[1] - 0.7);
  };
  auto m = calibrate::minimize(bowl, {0.9, 0.1}, {200, 0.15, 1e-6});
  EXPECT_EQ(m.method, "BOBYQA");
  EXPECT_NEAR(m.x[0], 0.3, 1e-3);
  EXPECT_NEAR(m.x[1], 0.7, 1e-3);
  EXPECT_TRUE(m.converged) << m.stop;
  EXPECT_LT(m.evaluations, 200) << "a quadratic is BOBYQA's model: it converges long before the budget";
  ASSERT_EQ(m.best_so_far.size(), static_cast<std::size_t>(m.evaluations));
  EXPECT_TRUE(std::is_sorted(m.best_so_far.rbegin(), m.best_so_far.rend())) << "the curve never rises";
  EXPECT_DOUBLE_EQ(m.best_so_far.back(), m.f);
  // One parameter (COBYLA) whose minimum lies outside [0, 1]: the answer is on the boundary, never beyond.
  auto edge = calibrate::minimize([](const std::vector<double>& u) { return (u[0] + 0.5) * (u[0] + 0.5); }, {0.5},
                                  {100, 0.15, 1e-4});
  EXPECT_EQ(edge.method, "COBYLA");
  EXPECT_GE(edge.x[0], 0.0);
  EXPECT_LT(edge.x[0], 0.01);
  // The budget is a hard limit and says so.
  auto capped = calibrate::minimize(bowl, {0.9, 0.1}, {7, 0.15, 1e-9});
  EXPECT_LE(capped.evaluations, 7);
  EXPECT_FALSE(capped.converged);
  EXPECT_EQ(capped.stop, "evaluation budget");
  // An objective that throws stops the search and the exception reaches the caller.
  EXPECT_THROW(calibrate::minimize([](const std::vector<double>&) -> double { throw std::runtime_error("render failed"); },
                                   {0.5, 0.5}),
               std::runtime_error);
}

calibrate::CalibrateOptions small_options(const TempDir& dir) {
  calibrate::CalibrateOptions o;
  o.scope.manifest = source_dir() / "shader_src" / "aovar.toml";
  o.algorithms = {"alchemy"};
  o.size = {96, 54};
  o.rays = 64;
  o.views.training = {{"builtin:stairs", "overview"}, {"builtin:cornell", "overview"}};
  o.views.holdout = {{"builtin:stairs", "closeup"}};
  o.budget.max_evaluations = 16;
  o.scope.cache_dir = dir / "cache";
  return o;
}

TEST(Calibrate, FittingLowersTrainingErrorWithinTheManifestsRanges) {
  TempDir dir;
  auto cal = calibrate::calibrate(small_options(dir));
  ASSERT_EQ(cal.fits.size(), 1u);
  const auto& f = cal.fits[0];
  EXPECT_EQ(f.algorithm, "alchemy");
  EXPECT_EQ(f.variant, "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp");
  // Alchemy's defaults over-darken against ray-traced occlusion (bench/HISTORY.md): the fit must find better.
  EXPECT_LT(f.train_rmse_after, 0.9 * f.train_rmse_before);
  EXPECT_LE(f.search.evaluations, 16);
  EXPECT_EQ(f.budget, 16);
  ASSERT_EQ(f.fitted.size(), 3u);  // intensity, contrast, bias are `fit = true`
  EXPECT_GE(f.fitted.at("ao.intensity"), 0.0);
  EXPECT_LE(f.fitted.at("ao.intensity"), 10.0);
  EXPECT_GE(f.fitted.at("ao.contrast"), 0.25);
  EXPECT_LE(f.fitted.at("ao.bias"), 0.05);
  ASSERT_EQ(f.views.size(), 3u);
  EXPECT_EQ(std::count_if(f.views.begin(), f.views.end(), [](const auto& v) { return v.training; }), 2);

  // The file round-trips the fitted values, and a broken file is one line naming it.
  calibrate::write_calibration(dir / "cal.json", cal);
  const auto manifest = small_options(dir).scope.manifest.get();
  auto loaded = calibrate::load_calibration(dir / "cal.json", manifest);
  EXPECT_EQ(loaded.at("alchemy"), f.fitted);
  util::write_atomic(dir / "bad.json", "{\"algorithms\": 3}");
  const std::string m = thrown_message<std::runtime_error>([&] {
    calibrate::load_calibration(dir / "bad.json", manifest);
  });
  EXPECT_NE(m.find("bad.json: error:"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;

  // measure --reference with the calibration: the row carries `error`, and the calibrated values beat the
  // defaults on a training view.
  measure::MeasureOptions mo;
  mo.scope.manifest = small_options(dir).scope.manifest;
  mo.scene = "builtin:stairs";
  mo.globs = {f.variant};
  mo.baseline = f.variant;
  mo.size = {96, 54};
  mo.timing.reps = 1;
  mo.truth.enabled = true;
  mo.truth.rays = 64;
  mo.scope.cache_dir = dir / "cache";
  mo.out = dir / "default";
  auto plain = measure::run_measure(mo);
  mo.calibration.values = loaded;
  mo.out = dir / "calibrated";
  auto tuned = measure::run_measure(mo);
  ASSERT_EQ(plain.rows.size(), 1u);
  ASSERT_TRUE(plain.rows[0].error && tuned.rows[0].error);
  EXPECT_LT(tuned.rows[0].error->rmse, plain.rows[0].error->rmse);
  EXPECT_NEAR(plain.rows[0].error->rmse, f.views[0].rmse_before, 1e-6) << "same variant, view, size, reference";
  auto json = nlohmann::json::parse(util::read_file(dir / "calibrated" / "measure.json").value());
  const auto& row = json.at("rows").at(0);
  EXPECT_NEAR(row.at("error").at("rmse").get<double>(), tuned.rows[0].error->rmse, 1e-12);
  for (const char* k : {"mae", "psnr", "ssim", "bias", "max", "share_over_0_1"}) EXPECT_TRUE(row.at("error").contains(k)) << k;
  EXPECT_TRUE(std::filesystem::exists(dir / "calibrated" / row.at("error_map").get<std::string>()));
  EXPECT_TRUE(std::filesystem::exists(dir / "calibrated" / "images" / "reference" / "overview.pfm"));
  // A re-run reuses the row, error included; without --reference the same inputs measure again.
  auto again = measure::run_measure(mo);
  EXPECT_EQ(again.reused, 1);
  ASSERT_TRUE(again.rows[0].error);
  EXPECT_DOUBLE_EQ(again.rows[0].error->rmse, tuned.rows[0].error->rmse);
  mo.truth.enabled = false;
  auto without = measure::run_measure(mo);
  EXPECT_EQ(without.reused, 0);
  EXPECT_FALSE(without.rows[0].error);
}

// Fits run several at once, each on its own device (CalibrateOptions::fits_at_once): the result is the one a
// fit at a time gives, in the same order, whatever finishes first.
TEST(Calibrate, FitsAtOnceGiveTheFitsOfOneAtATimeInTheSameOrder) {
  TempDir dir;
  auto o = small_options(dir);
  o.algorithms = {"sao", "alchemy", "hbao"};
  o.budget.max_evaluations = 6;
  o.fits_at_once = 1;
  const auto one = calibrate::calibrate(o);
  o.fits_at_once = 3;
  const auto three = calibrate::calibrate(o);
  ASSERT_EQ(one.fits.size(), 3u);
  ASSERT_EQ(three.fits.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(three.fits[i].algorithm, o.algorithms[i]);
    EXPECT_EQ(three.fits[i].algorithm, one.fits[i].algorithm);
    EXPECT_EQ(three.fits[i].fitted, one.fits[i].fitted) << one.fits[i].algorithm;
    EXPECT_EQ(three.fits[i].train_rmse_after, one.fits[i].train_rmse_after) << one.fits[i].algorithm;
    EXPECT_EQ(three.fits[i].search.evaluations, one.fits[i].search.evaluations) << one.fits[i].algorithm;
  }
}

// The split for a user's scene: every third view held out by default, the rest of --view held out when
// only training views are named, and one-line errors for what cannot be a split.
// --normals depth fits each method with its depth-normal variant (for scenes whose vertex normals lean from
// their faces); anything but buffer or depth is one line.
TEST(Calibrate, DepthNormalsFitTheMethodsDepthNormalVariant) {
  TempDir dir;
  auto o = small_options(dir);
  o.fit_normals = "depth";
  o.budget.max_evaluations = 4;
  auto cal = calibrate::calibrate(o);
  ASSERT_EQ(cal.fits.size(), 1u);
  EXPECT_EQ(cal.fits[0].variant, "alchemy-s16-p0-ndep-zdep-rst-d32-bsep-x1-hp");
  o.fit_normals = "rgb8";
  const std::string m = thrown_message<std::runtime_error>([&] { calibrate::calibrate(o); });
  EXPECT_NE(m.find("--normals must be buffer or depth"), std::string::npos) << m;
}

TEST(CalibrateViews, DefaultSplitHoldsOutEveryThirdViewAndErrorsAreOneLine) {
  auto split = calibrate::split_views({"builtin:stairs"}, {}, {}, {});
  using VC = calibrate::ViewCase;
  EXPECT_EQ(split.training, (std::vector<VC>{{"builtin:stairs", "overview"}, {"builtin:stairs", "closeup"}}));
  EXPECT_EQ(split.holdout, (std::vector<VC>{{"builtin:stairs", "background"}}));
  split = calibrate::split_views({"builtin:stairs", "builtin:cornell"}, {}, {"closeup"}, {});
  EXPECT_EQ(split.training, (std::vector<VC>{{"builtin:stairs", "closeup"}, {"builtin:cornell", "closeup"}}));
  EXPECT_EQ(split.holdout.size(), 4u) << "overview and background of both";
  split = calibrate::split_views({"builtin:stairs"}, {}, {}, {"overview"});
  EXPECT_EQ(split.holdout, (std::vector<VC>{{"builtin:stairs", "overview"}}));
  EXPECT_EQ(split.training.size(), 2u);
  auto error_of = [](auto&& f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string m = error_of([] { calibrate::split_views({"builtin:stairs"}, {}, {"nave"}, {}); });
  EXPECT_NE(m.find("scene builtin:stairs has no view 'nave' (its views: overview, closeup, background)"), std::string::npos) << m;
  m = error_of([] { calibrate::split_views({"builtin:stairs"}, {}, {"closeup"}, {"closeup"}); });
  EXPECT_NE(m.find("view 'closeup' is both a training view"), std::string::npos) << m;
  m = error_of([] { calibrate::split_views({"builtin:stairs"}, {}, {"overview", "closeup", "background"}, {}); });
  EXPECT_NE(m.find("has no held-out view"), std::string::npos) << m;
  m = error_of([] { calibrate::split_views({"builtin:stairs"}, {}, {}, {"overview", "closeup", "background"}); });
  EXPECT_NE(m.find("has no training view left"), std::string::npos) << m;
  for (const auto& text : {m}) EXPECT_EQ(text.find('\n'), std::string::npos);
  // Issue 54: ship's split names ship and only the options ship has (it has no --view).
  m = error_of([] { calibrate::split_views({"builtin:stairs"}, {}, {}, {"overview", "closeup", "background"}, "ship"); });
  EXPECT_EQ(m.rfind("ship: error: scene builtin:stairs has no training view left", 0), 0u) << m;
  EXPECT_NE(m.find("hold out fewer with --holdout-view"), std::string::npos) << m;
  EXPECT_EQ(m.find("--view)"), std::string::npos) << m;
  m = error_of([] { calibrate::split_views({"builtin:stairs"}, {}, {}, {"nave"}, "ship"); });
  EXPECT_EQ(m.rfind("ship: error: scene builtin:stairs has no view 'nave'", 0), 0u) << m;
}

// Auto-tune on one scene (here a built-in standing for the user's): the error falls on its training views
// and is reported on the held-out one, with the search's record; a per-variant fit lands under "variants"
// and wins over its algorithm's values when planning.
TEST(Calibrate, OnAScenesTrainingViewsReportsTheHeldOutView) {
  TempDir dir;
  auto o = small_options(dir);
  o.views = calibrate::split_views({"builtin:stairs"}, {}, {}, {});
  o.variants = {"alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp"};
  auto cal = calibrate::calibrate(o);
  ASSERT_EQ(cal.fits.size(), 1u);
  const auto& f = cal.fits[0];
  EXPECT_TRUE(f.per_variant);
  EXPECT_EQ(f.variant, o.variants[0]);
  EXPECT_LT(f.train_rmse_after, f.train_rmse_before);
  ASSERT_EQ(f.views.size(), 3u);
  EXPECT_EQ(f.views[2].view, "background");
  EXPECT_FALSE(f.views[2].training);
  EXPECT_GT(f.holdout_rmse_after, 0.0);
  EXPECT_EQ(f.search.method, "BOBYQA");
  EXPECT_EQ(static_cast<int>(f.search.best_so_far.size()), f.search.evaluations);

  calibrate::write_calibration(dir / "cal.json", cal);
  auto doc = nlohmann::json::parse(util::read_file(dir / "cal.json").value());
  EXPECT_TRUE(doc.at("algorithms").empty());
  ASSERT_TRUE(doc.at("variants").contains(f.variant));
  EXPECT_EQ(doc.at("variants").at(f.variant).at("search").at("evaluations").get<int>(), f.search.evaluations);
  EXPECT_EQ(doc.at("holdout").at(0).at("view"), "background");
  const auto manifest = o.scope.manifest.get();
  auto loaded = calibrate::load_calibration(dir / "cal.json", manifest);
  loaded["alchemy"] = {{"ao.intensity", 0.25}};
  compile::CompileOptions co;
  co.scope.targets = {variants::Target::vulkan};
  co.globs = {f.variant, "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp"};
  auto c = compile::compile_space(aovar::test::on_manifest(co, o.scope.manifest.path()));
  ASSERT_TRUE(c.ok());
  runner::RunnerOptions ro;
  ro.calibration = loaded;
  runner::VariantRunner runner(c, ro);
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto plan = runner.plan(static_cast<int>(v));
    const auto ao = std::find_if(plan.draws.begin(), plan.draws.end(), [](const auto& d) { return d.name == "ao"; });
    ASSERT_NE(ao, plan.draws.end());
    const bool own = c.space.variants[v].key == f.variant;
    EXPECT_FLOAT_EQ(ao->params.at(0), own ? static_cast<float>(f.fitted.at("ao.intensity")) : 0.25f)
        << c.space.variants[v].key;
  }
}

// A calibration file is checked against the manifest it is applied with: values past a parameter's range,
// parameters or algorithms the manifest lacks are refused in one line naming the file and the entry.
TEST(Calibrate, FileOutsideTheManifestsRangesIsRefused) {
  TempDir dir;
  const auto manifest = variants::load_manifest(source_dir() / "shader_src" / "aovar.toml");
  const std::pair<const char*, const char*> cases[] = {
      {R"({"algorithms": {"alchemy": {"params": {"ao.intensity": 12}}}})",
       "algorithms.alchemy: ao.intensity = 12 is outside the manifest's range [0, 10]"},
      {R"({"algorithms": {"alchemy": {"params": {"ao.contrast": -1}}}})", "ao.contrast = -1 is outside"},
      {R"({"algorithms": {"alchemy": {"params": {"ao.radius": 1}}}})", "'ao.radius' is not a parameter of the manifest's alchemy"},
      {R"({"algorithms": {"ssdo": {"params": {}}}})", "the manifest has no algorithm 'ssdo'"},
      {R"({"algorithms": {}, "variants": {"alchemy-s99": {"params": {}}}})", "variants.alchemy-s99: not a variant key"},
      {R"({"algorithms": {"alchemy": {"params": {"ao.intensity": "2"}}}})", "'ao.intensity' must be a number"}};
  for (const auto& [text, expected] : cases) {
    util::write_atomic(dir / "cal.json", text);
    try {
      calibrate::load_calibration(dir / "cal.json", manifest);
      ADD_FAILURE() << text << ": no error";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("cal.json: error: "), std::string::npos) << m;
      EXPECT_NE(m.find(expected), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  // And through the CLI: measure refuses the file before rendering anything.
  util::write_atomic(dir / "cal.json", std::get<0>(cases[0]));
  auto r = run_aovar("measure --calibration " + (dir / "cal.json").string() + " --size 32x18 --out " + (dir / "m").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("ao.intensity = 12 is outside the manifest's range"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "m" / "measure.json"));
}

// measure.json records the calibration it applied (file and content hash), and select's check of a table's
// calibration tells a table measured with another file (or none) apart from one measured with this one.
TEST(Calibrate, RunsRecordTheCalibrationTheyApplied) {
  TempDir dir;
  util::write_atomic(dir / "cal.json", R"({"algorithms": {"alchemy": {"params": {"ao.intensity": 1.5}}}})");
  util::write_atomic(dir / "other.json", R"({"algorithms": {"alchemy": {"params": {"ao.intensity": 2.5}}}})");
  auto r = run_aovar("measure --scene builtin:stairs --size 32x18 --reps 1 --warmup 0 --no-images --variants "
                     "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp --calibration " + (dir / "cal.json").string() +
                     " --cache-dir " + (dir / "cache").string() + " --out " + (dir / "m").string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto meta = nlohmann::json::parse(util::read_file(dir / "m" / "measure.json").value());
  const auto source = calibrate::calibration_source(dir / "cal.json");
  EXPECT_EQ(meta.at("calibration").at("hash"), source.hash);
  const table::CalibrationRef recorded{meta.at("calibration").at("file"), meta.at("calibration").at("hash"), {}};
  EXPECT_EQ(calibrate::measured_with(recorded, source, "m/measure.json"), "");
  const std::string other = calibrate::measured_with(recorded, calibrate::calibration_source(dir / "other.json"), "t.json");
  EXPECT_NE(other.find("t.json: error: measured with "), std::string::npos) << other;
  EXPECT_NE(other.find("measure again with --calibration"), std::string::npos) << other;
  EXPECT_NE(calibrate::measured_with(std::nullopt, source, "t.json").find("no calibration file recorded"),
            std::string::npos);
}

}  // namespace
}  // namespace aovar::test
