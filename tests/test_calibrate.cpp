// Calibration: the bounded minimiser, fitting a method against ray-traced references (error falls on the
// training views, values stay in range), the calibration file, and `measure --reference` with a calibration,
// progressive errors and flicker.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "calibrate/calibrate.h"
#include "compile/generate.h"
#include "measure/measure.h"
#include "render/plan.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

TEST(Calibrate, MinimizerFindsABowlsMinimumAndStaysInBounds) {
  int evaluations = 0;
  auto bowl = [](const std::vector<double>& u) {
    return (u[0] - 0.3) * (u[0] - 0.3) + 2 * (u[1] - 0.7) * (u[1] - 0.7) + 0.5 * (u[0] - 0.3) * (u[1] - 0.7);
  };
  auto best = calibrate::minimize(bowl, {0.9, 0.1}, 200, 0.15, 1e-5, &evaluations);
  EXPECT_NEAR(best[0], 0.3, 1e-3);
  EXPECT_NEAR(best[1], 0.7, 1e-3);
  EXPECT_LE(evaluations, 200);
  // The minimum of this one lies outside [0, 1] in u[0]: the answer is on the boundary, never beyond it.
  auto edge = calibrate::minimize([](const std::vector<double>& u) { return (u[0] + 0.5) * (u[0] + 0.5); }, {0.5}, 100);
  EXPECT_GE(edge[0], 0.0);
  EXPECT_LT(edge[0], 0.01);
  // The budget is a hard limit.
  calibrate::minimize(bowl, {0.9, 0.1}, 7, 0.15, 1e-9, &evaluations);
  EXPECT_LE(evaluations, 7);
}

calibrate::CalibrateOptions small_options(const TempDir& dir) {
  calibrate::CalibrateOptions o;
  o.manifest = source_dir() / "shader_src" / "aovar.toml";
  o.algorithms = {"alchemy"};
  o.size = {96, 54};
  o.rays = 64;
  o.training = {{"builtin:stairs", "overview"}, {"builtin:cornell", "overview"}};
  o.validation = {{"builtin:stairs", "closeup"}};
  o.max_evaluations = 16;
  o.reference_cache = dir / "cache";
  return o;
}

TEST(Calibrate, FittingLowersTrainingErrorWithinTheManifestsRanges) {
  TempDir dir;
  auto cal = calibrate::calibrate(small_options(dir));
  ASSERT_EQ(cal.fits.size(), 1u);
  const auto& f = cal.fits[0];
  EXPECT_EQ(f.algorithm, "alchemy");
  EXPECT_EQ(f.variant, "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp");
  // Alchemy's defaults over-darken against ray-traced occlusion (bench/README.md): the fit must find better.
  EXPECT_LT(f.train_rmse_after, 0.9 * f.train_rmse_before);
  EXPECT_LE(f.evaluations, 16);
  ASSERT_EQ(f.fitted.size(), 3u);  // intensity, contrast, bias are `fit = true`
  EXPECT_GE(f.fitted.at("ao.intensity"), 0.0);
  EXPECT_LE(f.fitted.at("ao.intensity"), 10.0);
  EXPECT_GE(f.fitted.at("ao.contrast"), 0.25);
  EXPECT_LE(f.fitted.at("ao.bias"), 0.05);
  ASSERT_EQ(f.views.size(), 3u);
  EXPECT_EQ(std::count_if(f.views.begin(), f.views.end(), [](const auto& v) { return v.training; }), 2);

  // The file round-trips the fitted values, and a broken file is one line naming it.
  calibrate::write_calibration(dir / "cal.json", cal);
  auto loaded = calibrate::load_calibration(dir / "cal.json");
  EXPECT_EQ(loaded.at("alchemy"), f.fitted);
  util::write_atomic(dir / "bad.json", "{\"algorithms\": 3}");
  try {
    calibrate::load_calibration(dir / "bad.json");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("bad.json: error:"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }

  // measure --reference with the calibration: the row carries `error`, and the calibrated values beat the
  // defaults on a training view.
  measure::MeasureOptions mo;
  mo.manifest = small_options(dir).manifest;
  mo.scene = "builtin:stairs";
  mo.globs = {f.variant};
  mo.baseline = f.variant;
  mo.size = {96, 54};
  mo.reps = 1;
  mo.ground_truth = true;
  mo.reference_rays = 64;
  mo.reference_cache = dir / "cache";
  mo.out = dir / "default";
  auto plain = measure::run_measure(mo);
  mo.calibration = loaded;
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
  mo.ground_truth = false;
  auto without = measure::run_measure(mo);
  EXPECT_EQ(without.reused, 0);
  EXPECT_FALSE(without.rows[0].error);
}

}  // namespace
}  // namespace aovar::test

namespace aovar::test {
namespace {

// --reference on a progressive variant: the converged error (halves averaged), the error of one frame
// alone, and flicker along the camera path; a non-progressive variant gets flicker only.
TEST(Measure, ReferenceGivesProgressiveVariantsOneFrameErrorAndFlicker) {
  TempDir dir;
  measure::MeasureOptions mo;
  mo.manifest = source_dir() / "shader_src" / "aovar.toml";
  mo.scene = "builtin:stairs";
  const std::string full = "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp";
  const std::string half = "alchemy-s16-p1-nrgb8-zdep-rst-d32-bsep-x1-hp";
  mo.globs = {full, half};
  mo.baseline = full;
  mo.size = {96, 54};
  mo.reps = 2;
  mo.ground_truth = true;
  mo.reference_rays = 64;
  mo.reference_cache = dir / "cache";
  auto r = measure::run_measure(mo);
  ASSERT_EQ(r.rows.size(), 2u);
  for (const auto& row : r.rows) {
    ASSERT_TRUE(row.error) << row.variant;
    ASSERT_TRUE(row.flicker) << row.variant;
    EXPECT_GT(*row.flicker, 0.0) << row.variant << ": the stairs' camera path moves";
    EXPECT_LT(*row.flicker, 0.1) << row.variant;
    EXPECT_EQ(row.error_one_frame.has_value(), row.variant == half) << row.variant;
  }
  const auto& p = r.rows[0].variant == half ? r.rows[0] : r.rows[1];
  // One frame has half the samples: its error differs from the converged one, both stay in a sane range.
  EXPECT_NE(p.error_one_frame->rmse, p.error->rmse);
  EXPECT_LT(p.error_one_frame->rmse, 0.3);
}

TEST(Plan, SingleFramePlanReadsThisFramesHalfTwice) {
  compile::CompileOptions co;
  co.targets = {variants::Target::vulkan};
  co.globs = {"alchemy-s16-p[01]-nrgb8-zdep-rst-d32-bsep-x1-hp"};
  auto c = compile::compile_space(source_dir() / "shader_src" / "aovar.toml", co);
  ASSERT_TRUE(c.ok());
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    auto plan = render::plan_pipeline(c, static_cast<int>(v), variants::Target::vulkan);
    auto one = render::plan_single_frame(plan);
    ASSERT_EQ(one.draws.size(), plan.draws.size());
    for (std::size_t d = 0; d < plan.draws.size(); ++d) {
      if (plan.draws[d].name != "progressive") {
        EXPECT_EQ(one.draws[d].inputs.size(), plan.draws[d].inputs.size());
        continue;
      }
      std::map<int, render::TextureRef> in(one.draws[d].inputs.begin(), one.draws[d].inputs.end());
      EXPECT_EQ(in.at(5).texture, in.at(6).texture);
      EXPECT_FALSE(in.at(6).previous) << "no history";
    }
  }
}

}  // namespace
}  // namespace aovar::test
