// Runtime skipping (render/plan.h): fullscreen draws reject background pixels in the depth test, before
// their fragment shaders run. The images must not change, and the pixels not shaded must be exactly the
// background, on both backends.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "profile/profile.h"
#include "render/plan.h"
#include "render_support.h"
#include "test_support.h"
#include "variants/manifest.h"

namespace aovar::test {
namespace {

const std::vector<std::string> kSkipBackends = {"lavapipe", "osmesa"};
// Every method of the shipped manifest.
const std::vector<std::string>& skip_methods() {
  static const std::vector<std::string> methods = [] {
    std::vector<std::string> out;
    const auto m = variants::load_manifest(source_dir() / "shader_src/aovar.toml");
    for (const auto& v : m.axis_values(variants::Axis::algorithm)) out.push_back(v.text);
    return out;
  }();
  return methods;
}
const render::Extent kSize{160, 90};

// Per method: render_support's three kinds (full resolution plain and blurred, half-resolution progressive
// mediump on r16f depth) and a quarter-resolution bilateral one, so every skipped draw kind and both masks
// (the G-buffer's depth, the background_mask pass) take part.
const PickedVariants& picked() {
  static const PickedVariants p = [] {
    std::vector<std::vector<std::string>> kinds;
    for (const auto& a : skip_methods()) {
      for (auto& k : method_kinds(a)) kinds.push_back(k);
      kinds.push_back({a + "-s08-p0-nrgb8-zpos-rst-d32-bbil-x4-hp", a + "-s08-p0-*-d32-bbil-x4-hp"});
    }
    return pick_variants(kinds);
  }();
  return p;
}

// The atrium from its overview eye pitched until about 40 % of the frame is sky.
struct SkyScene {
  scene::Scene scene;
  scene::View view;
  double sky_share = 0;
};
const SkyScene& sky() {
  static const SkyScene s = [] {
    SkyScene out;
    out.scene = scene::load_scene("builtin:atrium");
    auto views = profile::sky_sweep(out.scene, out.scene.views.front(), 7, kSize);
    auto best = std::min_element(views.begin(), views.end(), [](const auto& a, const auto& b) {
      return std::abs(a.background_share - 0.4) < std::abs(b.background_share - 0.4);
    });
    out.view = best->view;
    out.sky_share = best->background_share;
    return out;
  }();
  return s;
}

bool skips(const render::PipelinePlan& plan) {
  return std::any_of(plan.draws.begin(), plan.draws.end(),
                     [](const render::Draw& d) { return d.depth == render::DepthUse::skip_background; });
}

TEST(BackgroundSkip, ImagesMatchTheFullyShadedPlanOnBothBackends) {
  const auto& p = picked();
  const auto& s = sky();
  ASSERT_GT(s.sky_share, 0.2);
  ASSERT_LT(s.sky_share, 0.6);
  ASSERT_GE(p.keys.size(), 3 * skip_methods().size());
  for (const auto& backend_name : kSkipBackends) {
    auto backend = render::make_backend(backend_name, {});
    backend->set_scene(s.scene);
    int masked = 0;
    for (const auto& [kind, key] : p.keys) {
      auto plan = render::plan_pipeline(p.compiled, variant_index(p.compiled, key), target_of(backend_name));
      ASSERT_TRUE(skips(plan)) << key;
      auto shaded = render::plan_without_background_skip(plan);
      ASSERT_FALSE(skips(shaded)) << key;
      masked += std::any_of(plan.draws.begin(), plan.draws.end(),
                            [](const render::Draw& d) { return d.depth == render::DepthUse::write_mask; });
      // Four frames: progressive variants average with the previous frame's half.
      auto a = render_plan(*backend, plan, s.view, kSize, s.scene.ao_radius, 4);
      auto b = render_plan(*backend, shaded, s.view, kSize, s.scene.ao_radius, 4);
      ASSERT_EQ(a.pixels.size(), b.pixels.size()) << key;
      int differ = 0;
      for (std::size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != b.pixels[i];
      EXPECT_EQ(differ, 0) << backend_name << " " << key << ": " << differ << " pixels changed by skipping";
    }
    EXPECT_GE(masked, 2 * static_cast<int>(skip_methods().size())) << "reduced-resolution variants draw a mask";
  }
}

// The AO draw's output starts at a sentinel no shader writes: the pixels still holding it afterwards were
// not shaded. At full resolution they are exactly the pixels no triangle covered; at quarter resolution
// (the background_mask pass) their share is the sky's. The fully shaded plan leaves none.
TEST(BackgroundSkip, TheRasteriserRejectsExactlyTheBackground) {
  const auto& s = sky();
  auto c = compile_variants({"alchemy-s08-p0-nrgb8-zdep-rst-d32-bno-x1-hp", "alchemy-s08-p0-nrgb8-zdep-rst-d32-bbil-x4-hp"});
  ASSERT_EQ(c.space.variants.size(), 2u);
  const float sentinel = -1.0f;
  for (const auto& backend_name : kSkipBackends) {
    auto backend = render::make_backend(backend_name, {});
    backend->set_scene(s.scene);
    for (int v = 0; v < 2; ++v) {
      const std::string key = c.space.variants[v].key;
      auto full = render::plan_pipeline(c, v, target_of(backend_name));
      auto depth_plan = render::plan_prefix(full, "gbuffer");
      auto depth = render_plan(*backend, depth_plan, s.view, kSize, s.scene.ao_radius, 1);
      const float background = render::background_depth(s.view.far_plane);
      int sky_pixels = 0;
      for (float z : depth.pixels) sky_pixels += z == background;

      for (bool skip : {true, false}) {
        auto ao = render::plan_prefix(skip ? full : render::plan_without_background_skip(full), "ao");
        ao.textures[ao.result].cleared = true;
        ao.textures[ao.result].clear = {sentinel, sentinel, sentinel, sentinel};
        auto img = render_plan(*backend, ao, s.view, kSize, s.scene.ao_radius, 1);
        int unshaded = 0;
        for (float x : img.pixels) unshaded += x == sentinel;
        SCOPED_TRACE(fmt::format("{} {} skip {}", backend_name, key, skip));
        if (!skip) {
          EXPECT_EQ(unshaded, 0);
        } else if (full.resolution >= 1.0) {
          ASSERT_EQ(img.pixels.size(), depth.pixels.size());
          for (std::size_t i = 0; i < img.pixels.size(); ++i)
            ASSERT_EQ(img.pixels[i] == sentinel, depth.pixels[i] == background) << "pixel " << i;
          EXPECT_GT(sky_pixels, 0);
        } else {
          const double share = double(unshaded) / double(img.pixels.size());
          EXPECT_NEAR(share, double(sky_pixels) / double(depth.pixels.size()), 0.05);
        }
      }
    }
  }
}

}  // namespace
}  // namespace aovar::test
