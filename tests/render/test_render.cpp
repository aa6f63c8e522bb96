// Rendering through both backends: every built-in scene, backend agreement, AO on known geometry,
// progressive halves, and the cost ordering of sample counts.
#include <gtest/gtest.h>

#include "image/health.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include <fmt/format.h>

#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const std::vector<std::string> kRenderBackends = {"lavapipe", "osmesa"};

// A handful of variants covering every buffer format, blur, resolution and precision choice.
const std::vector<std::string> kVariety = {
    "alchemy-s08-p0-nrg8-zdep-rst-d32-bsep-x1-hp",
    "alchemy-s04-p1-noct-zpos-rip-d16-bbil-x2-hp",
    "alchemy-s16-p0-ndep-zdep-rst-d16-bsep-x4-mp",
    "alchemy-s12-p0-nrgb8-zdep-rip-d32-bno-x1-hp",
};

const compile::CompiledSpace& variety() {
  static const compile::CompiledSpace c = compile_variants(kVariety);
  return c;
}

struct SceneCase {
  std::string backend, scene;
};

class EveryScene : public ::testing::TestWithParam<SceneCase> {};

TEST_P(EveryScene, RendersFiniteOcclusionInRangeWithEveryVariant) {
  const auto& [backend_name, scene_name] = GetParam();
  auto sc = scene::load_scene(scene_name);
  auto backend = render::make_backend(backend_name, {});
  backend->set_scene(sc);
  const auto& c = variety();
  for (const auto& key : kVariety) {
    auto plan = render::plan_pipeline(c, variant_index(c, key), target_of(backend_name));
    auto img = render_plan(*backend, plan, sc.views.front(), {160, 90}, sc.ao_radius, 3);
    auto h = image::health(img);
    EXPECT_EQ(h.nan, 0) << key;
    EXPECT_EQ(h.inf, 0) << key;
    EXPECT_EQ(h.out_of_range, 0) << key;
    float lo = 1, hi = 0;
    for (float v : img.pixels) lo = std::min(lo, v), hi = std::max(hi, v);
    EXPECT_LT(lo, 0.8f) << key << ": the overview shows contacts, something must be occluded";
    EXPECT_GT(hi, 0.95f) << key << ": open surfaces or background must stay bright";
  }
}

INSTANTIATE_TEST_SUITE_P(Builtin, EveryScene,
                         ::testing::Values(SceneCase{"lavapipe", "builtin:atrium"}, SceneCase{"osmesa", "builtin:atrium"},
                                           SceneCase{"lavapipe", "builtin:spheres"}, SceneCase{"osmesa", "builtin:spheres"},
                                           SceneCase{"lavapipe", "builtin:stairs"}, SceneCase{"osmesa", "builtin:stairs"},
                                           SceneCase{"lavapipe", "builtin:cornell"}, SceneCase{"osmesa", "builtin:cornell"}),
                         [](const auto& info) {
                           return info.param.backend + "_" + info.param.scene.substr(info.param.scene.find(':') + 1);
                         });

TEST(Render, LavapipeAndOsmesaAgree) {
  auto sc = scene::load_scene("builtin:atrium");
  const auto& c = variety();
  std::map<std::string, image::FloatImage> images[2];
  for (int b = 0; b < 2; ++b) {
    auto backend = render::make_backend(kRenderBackends[b], {});
    backend->set_scene(sc);
    for (const auto& key : kVariety) {
      auto plan = render::plan_pipeline(c, variant_index(c, key), target_of(kRenderBackends[b]));
      images[b][key] = render_plan(*backend, plan, sc.views.front(), {320, 180}, sc.ao_radius, 3);
    }
  }
  for (const auto& key : kVariety) {
    auto d = compare(images[0][key], images[1][key]);
    EXPECT_LE(d.mean_abs, 1.0 / 255.0) << key;
    EXPECT_LE(d.max_abs, 0.1) << key;
  }
}

// Each variety variant rendered on each backend: `check(backend, key, image)`.
void for_each_variety_image(const scene::Scene& sc, const scene::View& view, render::Extent size, float radius,
                            const std::function<void(const std::string&, const std::string&, const image::FloatImage&)>& check) {
  const auto& c = variety();
  for (const auto& b : kRenderBackends) {
    auto backend = render::make_backend(b, {});
    backend->set_scene(sc);
    for (const auto& key : kVariety)
      check(b, key, render_plan(*backend, render::plan_pipeline(c, variant_index(c, key), target_of(b)), view, size, radius, 3));
  }
}

TEST(Render, OpenPlaneIsOpenOnBothBackends) {
  auto view = floor_view();
  auto sc = quad_scene({kFloor}, view, 0.5f);
  for_each_variety_image(sc, view, {160, 90}, sc.ao_radius, [](const std::string& b, const std::string& key, const auto& img) {
    EXPECT_GE(*std::min_element(img.pixels.begin(), img.pixels.end()), 0.95f) << b << " " << key;
  });
}

TEST(Render, InnerCornerIsDarkerThanTheOpenFloorNextToIt) {
  const CornerProbe p = corner_probe();
  for_each_variety_image(p.scene, p.view, p.size, p.radius, [&](const std::string& b, const std::string& key, const auto& img) {
    EXPECT_GE(img.at(p.open.x, p.open.y), 0.95f) << b << " " << key;
    EXPECT_LT(img.at(p.corner.x, p.corner.y), img.at(p.open.x, p.open.y) - 0.1f) << b << " " << key;
  });
}

TEST(Render, ProgressiveHalvesAlternateAndAverageToTheFullKernel) {
  const std::string half = "alchemy-s16-p1-nrg8-zdep-rst-d32-bsep-x1-hp";
  const std::string full = "alchemy-s16-p0-nrg8-zdep-rst-d32-bsep-x1-hp";
  auto c = compile_variants({half, full});
  auto sc = scene::load_scene("builtin:stairs");
  const auto& view = sc.views.front();
  for (const auto& b : kRenderBackends) {
    auto backend = render::make_backend(b, {});
    backend->set_scene(sc);
    // The raw AO pass of each frame (before averaging and blur): parity 0 and 1 use different samples.
    auto half_plan = render::plan_prefix(render::plan_pipeline(c, variant_index(c, half), target_of(b)), "ao");
    auto full_plan = render::plan_prefix(render::plan_pipeline(c, variant_index(c, full), target_of(b)), "ao");
    auto even = render_plan(*backend, half_plan, view, {320, 180}, sc.ao_radius, 1, 0);
    auto odd = render_plan(*backend, half_plan, view, {320, 180}, sc.ao_radius, 1, 1);
    auto all = render_plan(*backend, full_plan, view, {320, 180}, sc.ao_radius, 1, 0);
    EXPECT_GT(compare(even, odd).mean_abs, 0.005) << b << ": the two halves must see different samples";
    image::FloatImage avg = even;
    for (std::size_t i = 0; i < avg.pixels.size(); ++i) avg.pixels[i] = 0.5f * (even.pixels[i] + odd.pixels[i]);
    // Alchemy is linear in the tap sum until its max(0, .) clamps, so the average of the halves is the
    // full kernel except where a pixel is almost fully occluded.
    EXPECT_LT(compare(avg, all).mean_abs, 0.01) << b;

    // The whole progressive pipeline (average of this half and the previous frame's other half, then the
    // blur) on a static camera matches the full-kernel pipeline.
    auto prog = render_plan(*backend, render::plan_pipeline(c, variant_index(c, half), target_of(b)), view,
                            {320, 180}, sc.ao_radius, 4);
    auto ref = render_plan(*backend, render::plan_pipeline(c, variant_index(c, full), target_of(b)), view,
                           {320, 180}, sc.ao_radius, 2);
    EXPECT_LT(compare(prog, ref).mean_abs, 0.01) << b;
  }
}

TEST(Render, CameraPathMovesTheViewAndLoops) {
  const std::string key = "alchemy-s08-p0-nrg8-zdep-rst-d32-bsep-x1-hp";
  const auto& c = variety();
  auto sc = scene::load_scene("builtin:spheres");
  const scene::View& view = sc.views.front();
  ASSERT_GT(glm::length(view.path_offset), 0.0f);
  auto backend = render::make_backend("lavapipe", {});
  backend->set_scene(sc);
  auto p = backend->prepare(render::plan_pipeline(c, variant_index(c, key), variants::Target::vulkan), {160, 90});
  auto frame = [&](int f) {
    render::FrameSetup s;
    s.view = &view;
    s.frame = f;
    s.radius = sc.ao_radius;
    backend->render(*p, s);
    return backend->read_result(*p);
  };
  auto first = frame(0), last = frame(view.path_frames - 1), looped = frame(view.path_frames);
  EXPECT_GT(compare(first, last).mean_abs, 1e-3) << "the camera moved along the path";
  EXPECT_EQ(compare(first, looped).max_abs, 0.0) << "frame path_frames is the path's first pose again";
}

}  // namespace
}  // namespace aovar::test
