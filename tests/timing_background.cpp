// Timing test (run serially, label "timing"): background pixels are rejected before the AO pass's fragment
// shader (render/plan.h), so its time falls as the sky grows (issue 8, runtime skipping; figures in
// bench/README.md, bench/background).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "compile/generate.h"
#include "profile/profile.h"
#include "render/backend.h"
#include "render_support.h"
#include "scene/scene.h"
#include "test_support.h"

namespace aovar::test {
namespace {

// Runtime skipping: background pixels are not shaded, so the AO pass time falls as the sky grows. Three views of the atrium from one eye, about 10 %, 50 % and 90 % sky, timed interleaved (median of
// 15 rounds); the gaps are several times the noise of this host.
TEST(Profile, AoPassTimeFallsAsTheSkyGrows) {
  const auto c = compile_variants({"alchemy-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp"}, {variants::Target::vulkan});
  ASSERT_EQ(c.space.variants.size(), 1u);
  const auto sc = scene::load_scene("builtin:atrium");
  const render::Extent size{320, 180};
  auto sweep = profile::sky_sweep(sc, sc.views.front(), 12, size);
  ASSERT_EQ(sweep.size(), 12u);
  EXPECT_LT(sweep.front().background_share, 0.1);
  EXPECT_GT(sweep.back().background_share, 0.9);
  auto nearest = [&](double share) {
    return *std::min_element(sweep.begin(), sweep.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.background_share - share) < std::abs(b.background_share - share);
    });
  };
  std::vector<profile::SkyView> views = {nearest(0.1), nearest(0.5), nearest(0.9)};
  auto backend = render::make_backend("lavapipe", {});
  auto t = profile::time_against_background(*backend, render::plan_pipeline(c, 0, variants::Target::vulkan), sc, views,
                                            size, 15);
  ASSERT_EQ(t.size(), 3u);
  for (const auto& x : t) EXPECT_GT(x.ao_ms, 0.0);
  EXPECT_GT(t[0].ao_ms, t[1].ao_ms) << "sky " << t[0].background_share << " vs " << t[1].background_share;
  EXPECT_GT(t[1].ao_ms, t[2].ao_ms) << "sky " << t[1].background_share << " vs " << t[2].background_share;
  EXPECT_LT(t[2].ao_ms, 0.5 * t[0].ao_ms);
}

}  // namespace
}  // namespace aovar::test
