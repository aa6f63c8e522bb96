// A plan's draw indices are computed on the plan that runs (issue 54, reproduction 8): at small sizes
// render::plan_for_size drops MIP draws, so the full plan's index of the AO draw names another draw of the
// prepared pipeline. Calibration sets parameters on the AO draw of the plan the backend runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "calibrate/calibrate.h"
#include "compile/generate.h"
#include "render/plan.h"
#include "test_support.h"

namespace aovar::test {
namespace {

std::size_t index_in_full_plan(const render::PipelinePlan& plan, const std::string& name) {
  const auto it = std::find_if(plan.draws.begin(), plan.draws.end(), [&](const auto& d) { return d.name == name; });
  return static_cast<std::size_t>(it - plan.draws.begin());
}

// Every draw of SAO's (the method with a depth pyramid) at the smallest sizes: the index names that draw in
// the plan that runs, and at 8x8 it is not the full plan's index (the reproduction's mix-up).
TEST(DrawIndexAtSize, NamesTheDrawOfThePlanThatRunsAtTheSmallestSizes) {
  compile::CompileOptions o;
  o.scope.targets = {variants::Target::vulkan};
  o.globs = {"sao-s12-p1-ndep-zdep-rst-d32-bbil-x4-hp"};
  const auto c = compile::compile_space(on_manifest(o, source_dir() / "shader_src" / "aovar.toml"));
  ASSERT_TRUE(c.ok() && c.space.variants.size() == 1u);
  const render::PipelinePlan plan = render::plan_pipeline(c, 0, variants::Target::vulkan);
  for (const render::Extent size : {render::Extent{1, 1}, render::Extent{2, 2}, render::Extent{4, 4},
                                    render::Extent{8, 8}, render::Extent{16, 9}, render::Extent{64, 36}}) {
    SCOPED_TRACE(std::to_string(size.width) + "x" + std::to_string(size.height));
    const auto ran = render::plan_for_size(plan, size);
    const std::size_t ao = render::draw_index_at_size(plan, size, "ao");
    ASSERT_LT(ao, ran.draws.size());
    EXPECT_EQ(ran.draws[ao].name, "ao");
    if (size.width <= 8) {
      EXPECT_LT(ao, index_in_full_plan(plan, "ao")) << "MIP draws were dropped before it";
    }
  }
  EXPECT_THROW(render::draw_index_at_size(plan, {8, 8}, "no-such-draw"), std::runtime_error);
}

// The reproduction: calibrate --algorithms sao --size 8x8 failed with "set_params: draw 7 of 8 takes 3
// floats, got 4"; it fits now, and so does the smallest size of all.
TEST(DrawIndexAtSize, CalibrateFitsSaoAtTheSmallestSizes) {
  for (const render::Extent size : {render::Extent{8, 8}, render::Extent{1, 1}}) {
    TempDir dir;
    calibrate::CalibrateOptions o;
    o.scope.manifest = source_dir() / "shader_src" / "aovar.toml";
    o.scope.cache_dir = dir / "cache";
    o.algorithms = {"sao"};
    o.size = size;
    o.rays = 8;
    o.views.training = {{"builtin:stairs", "overview"}};
    o.views.holdout = {{"builtin:stairs", "closeup"}};
    o.budget.max_evaluations = 4;
    const auto cal = calibrate::calibrate(o);
    ASSERT_EQ(cal.fits.size(), 1u);
    EXPECT_EQ(cal.fits[0].algorithm, "sao");
    EXPECT_FALSE(cal.fits[0].fitted.empty());
  }
}

}  // namespace
}  // namespace aovar::test
