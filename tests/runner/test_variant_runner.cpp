// The variant runner (src/runner): plans carry the calibration (a variant's entry over its algorithm's, the
// caller's overrides over both), the backend decides the target, stills render the frames a progressive
// variant needs, camera paths keep the frames asked for, the scene is uploaded once per object, and scoring
// against a reference (the error, its breakdown where the depth is known, the screen-edge band). Small
// frames on lavapipe and osmesa only.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render_support.h"
#include "runner/score.h"
#include "runner/variant_runner.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const char* kStill = "alchemy-s08-p0-nrg8-zdep-rst-d32-bno-x1-hp";
const char* kProgressive = "alchemy-s08-p1-nrg8-zdep-rst-d32-bsep-x1-hp";
const CompiledVariants kRunnerVariants({kStill, kProgressive});

runner::RunnerOptions tiny(const std::string& backend = "lavapipe") {
  runner::RunnerOptions o;
  o.backend = backend;
  o.size = {64, 36};
  return o;
}

// Every draw's parameter block of a plan, in order.
std::vector<std::vector<float>> params_of(const render::PipelinePlan& plan) {
  std::vector<std::vector<float>> out;
  for (const auto& d : plan.draws) out.push_back(d.params);
  return out;
}

TEST(VariantRunner, FindsVariantsByKeyAndPlansForItsBackendsTarget) {
  const auto& c = kRunnerVariants.space();
  const int still = runner::find_variant(c, kStill);
  ASSERT_GE(still, 0);
  EXPECT_EQ(c.space.variants[still].key, kStill);
  EXPECT_EQ(runner::find_variant(c, "alchemy-not-a-key"), -1);

  runner::VariantRunner vk(c, tiny("lavapipe")), gl(c, tiny("osmesa"));
  EXPECT_EQ(vk.target(), variants::Target::vulkan);
  EXPECT_EQ(gl.target(), variants::Target::gl45);
  EXPECT_EQ(vk.device().backend, "lavapipe");
  EXPECT_EQ(gl.device().backend, "osmesa");
  EXPECT_EQ(vk.size(), (render::Extent{64, 36}));
  EXPECT_FALSE(vk.plan(still).shaders.front().spirv.empty()) << "vulkan plans carry SPIR-V";
  EXPECT_FALSE(gl.plan(still).shaders.front().glsl.empty()) << "gl45 plans carry GLSL";
}

TEST(VariantRunner, PlansTakeTheVariantsCalibrationOverItsAlgorithmsAndTheCallersOverBoth) {
  const auto& c = kRunnerVariants.space();
  const int v = runner::find_variant(c, kStill);
  auto plan_with = [&](const render::ParamOverrides& values) {
    return params_of(render::plan_pipeline(c, v, variants::Target::vulkan, values));
  };
  // The premise: each value below gives another plan (the default is none of them).
  for (double value : {3.0, 4.0, 5.0}) ASSERT_NE(plan_with({}), plan_with({{"ao.intensity", value}})) << value;
  ASSERT_NE(plan_with({{"ao.intensity", 3.0}}), plan_with({{"ao.intensity", 4.0}}));

  auto o = tiny();
  o.calibration["alchemy"] = {{"ao.intensity", 3.0}};
  runner::VariantRunner by_algorithm(c, o);
  EXPECT_EQ(params_of(by_algorithm.plan(v)), plan_with({{"ao.intensity", 3.0}}));
  EXPECT_EQ(params_of(by_algorithm.plan(v, {{"ao.intensity", 5.0}})), plan_with({{"ao.intensity", 5.0}}));

  o.calibration[kStill] = {{"ao.intensity", 4.0}};
  runner::VariantRunner by_variant(c, o);
  EXPECT_EQ(params_of(by_variant.plan(v)), plan_with({{"ao.intensity", 4.0}}));
  EXPECT_EQ(params_of(by_variant.plan(v, {{"ao.intensity", 5.0}})), plan_with({{"ao.intensity", 5.0}}));

  o.calibration.erase("alchemy");
  o.calibration.erase(kStill);
  o.calibration["gtao"] = {{"ao.intensity", 6.0}};
  runner::VariantRunner other_algorithm(c, o);
  EXPECT_EQ(params_of(other_algorithm.plan(v)), plan_with({})) << "another algorithm's entry does not apply";
}

// A still of a progressive variant is frame 1 (both halves); of the others frame 0. Its health and mean
// visibility are those of the image read back.
TEST(VariantRunner, StillsRenderTheFramesAProgressiveVariantNeeds) {
  const auto& c = kRunnerVariants.space();
  auto sc = scene::load_scene("builtin:stairs");
  const scene::View& view = sc.views.front();
  runner::VariantRunner r(c, tiny());
  r.use_scene(sc);
  for (const char* key : {kStill, kProgressive}) {
    SCOPED_TRACE(key);
    const auto plan = r.plan(runner::find_variant(c, key));
    auto pipeline = r.prepare(plan);
    const runner::Still still = r.render_still(*pipeline, plan, view, sc.ao_radius);
    const auto by_hand = render_plan(r.backend(), plan, view, r.size(), sc.ao_radius, plan.progressive ? 2 : 1);
    EXPECT_EQ(still.image.pixels, by_hand.pixels);
    if (plan.progressive) {
      const auto one_frame = render_plan(r.backend(), plan, view, r.size(), sc.ao_radius, 1);
      EXPECT_NE(still.image.pixels, one_frame.pixels) << "frame 0 alone has half the samples";
    }
    EXPECT_EQ(still.health.nan + still.health.inf + still.health.out_of_range, 0);
    double sum = 0;
    for (float p : still.image.pixels) sum += p;
    EXPECT_NEAR(still.mean_visibility, sum / static_cast<double>(still.image.pixels.size()), 1e-9);
    EXPECT_LT(still.mean_visibility, 1.0) << "the stairs occlude somewhere";
    EXPECT_GT(still.mean_visibility, 0.0);
  }
}

// A camera path keeps the last `count` of first + count frames, and the camera moves between them.
TEST(VariantRunner, PathsKeepTheFramesAskedForAlongAMovingCamera) {
  const auto& c = kRunnerVariants.space();
  auto sc = scene::load_scene("builtin:stairs");
  runner::VariantRunner r(c, tiny());
  r.use_scene(sc);
  const auto plan = r.plan(runner::find_variant(c, kStill));
  auto pipeline = r.prepare(plan);
  const auto frames = r.render_path(*pipeline, sc.views.front(), sc.ao_radius, 1, 2);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_NE(frames[0].pixels, frames[1].pixels) << "frames 1 and 2 of the path see different things";
  const auto again = r.render_path(*pipeline, sc.views.front(), sc.ao_radius, 2, 1);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].pixels, frames[1].pixels) << "frame 2 is frame 2 whatever was kept before it";
}

// use_scene uploads a scene object once: a second call with the same object is no upload (what a caller that
// changes a scene in place must know), another object is.
TEST(VariantRunner, UsesASceneObjectOnceAndAnotherObjectAgain) {
  const auto& c = kRunnerVariants.space();
  scene::View view = floor_view();
  scene::Scene open = quad_scene({kFloor}, view, 0.5f), walled = quad_scene({kFloor, kWall}, view, 0.5f);
  runner::VariantRunner r(c, tiny());
  const auto plan = r.plan(runner::find_variant(c, kStill));
  auto pipeline = r.prepare(plan);
  auto still = [&] { return r.render_still(*pipeline, plan, view, 0.5f).mean_visibility; };
  r.use_scene(open);
  const double open_floor = still();
  EXPECT_GT(open_floor, 0.95);
  r.use_scene(walled);
  const double with_wall = still();
  EXPECT_LT(with_wall, open_floor) << "another object is uploaded";
  walled = open;  // the same object, changed in place: not uploaded again
  r.use_scene(walled);
  EXPECT_EQ(still(), with_wall);
}

TEST(VariantRunner, UnknownBackendIsABackendError) {
  const std::string m = thrown_message([] { runner::VariantRunner r(kRunnerVariants.space(), tiny("metal")); });
  EXPECT_TRUE(has_text(m, "metal")) << m;
  EXPECT_THROW(runner::VariantRunner(kRunnerVariants.space(), tiny("metal")), render::BackendError);
}

// The band is the AO radius in pixels at the median depth: it halves when the depth doubles, is capped at a
// quarter of the shorter side, and is 0 where no geometry gives a median.
TEST(Score, EdgeBandIsTheRadiusInPixelsAtTheMedianDepth) {
  const scene::View view = floor_view();
  const render::Extent size{320, 180};
  const double at_10 = runner::edge_band_px(view, 0.5f, size, 10.0), at_20 = runner::edge_band_px(view, 0.5f, size, 20.0);
  ASSERT_GT(at_10, 0.0);
  EXPECT_NEAR(at_20, at_10 / 2, 1e-9 * at_10);
  EXPECT_NEAR(runner::edge_band_px(view, 1.0f, size, 20.0), at_10, 1e-9 * at_10) << "twice the radius, twice as far";
  EXPECT_EQ(runner::edge_band_px(view, 0.5f, size, 1e-6), 0.25 * 180);
  EXPECT_EQ(runner::edge_band_px(view, 0.5f, size, 0.0), 0.0);
  EXPECT_EQ(runner::edge_band_px(view, 0.5f, size, std::numeric_limits<double>::quiet_NaN()), 0.0);
  EXPECT_EQ(runner::edge_band_px(view, 0.5f, size, std::numeric_limits<double>::infinity()), 0.0);
}

// Scoring compares the geometry pixels only, and breaks the error down where the reference has a depth of
// the image's size.
TEST(Score, ComparesGeometryPixelsAndBreaksDownWhereTheDepthIsKnown) {
  reference::ReferenceImage truth;
  truth.visibility = {4, 2, std::vector<float>(8, 0.5f)};
  truth.depth = {4, 2, {2, 3, 4, 5, 6, 7, 8, 9}};
  truth.background.assign(8, 0);
  truth.background[7] = 1;
  truth.depth.pixels[7] = std::numeric_limits<float>::infinity();
  image::FloatImage img = truth.visibility;
  img.pixels[0] = 0.7f;  // one geometry pixel 0.2 too light
  img.pixels[7] = 0.0f;  // background: not compared
  const scene::View view = floor_view();

  const metrics::ErrorStats plain = runner::score(img, truth);
  EXPECT_EQ(plain.finite, 7);
  EXPECT_NEAR(plain.max, 0.2, 1e-6);
  EXPECT_NEAR(plain.bias, 0.2 / 7, 1e-6);
  EXPECT_FALSE(plain.breakdown);
  const metrics::ErrorStats with_depth = runner::score(img, truth, view, 0.5f);
  EXPECT_TRUE(with_depth.breakdown);
  EXPECT_EQ(with_depth.rmse, plain.rmse);
  truth.depth = {};  // a reference loaded from files holds no depth
  EXPECT_FALSE(runner::score(img, truth, view, 0.5f).breakdown);
}

}  // namespace
}  // namespace aovar::test
