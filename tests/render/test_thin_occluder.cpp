// Thin-occluder compensation of the horizon methods (GTAO, HBAO; Strugar 2021, XeGTAO's ThinOccluderCompensation):
// a thin pole standing on the floor darkens the floor around its foot less once the compensation is on, and a
// thick wall's contact still darkens with it on. VBAO's thickness does the same job by construction: a thinner
// assumed occluder leaves the floor around the pole lighter.
#include <gtest/gtest.h>

#include <memory>

#include "render/plan.h"
#include "render_support.h"

namespace aovar::test {
namespace {

constexpr float kRadius = 0.5f;
const render::Extent kSize{320, 180};

// An axis-aligned box of width w (x and z) and height h standing on the floor, centred at (x, z): four sides
// and a top, outward normals.
std::vector<Quad> pole(float x, float z, float w, float h) {
  float x0 = x - 0.5f * w, x1 = x + 0.5f * w, z0 = z - 0.5f * w, z1 = z + 0.5f * w;
  return {{{x0, 0, z1}, {w, 0, 0}, {0, h, 0}},  {{x1, 0, z0}, {-w, 0, 0}, {0, h, 0}},
          {{x1, 0, z1}, {0, 0, -w}, {0, h, 0}}, {{x0, 0, z0}, {0, 0, w}, {0, h, 0}},
          {{x0, h, z1}, {w, 0, 0}, {0, 0, -w}}};
}

// The method's plain and blurred variants (render_support.h's first two kinds), those the manifest has. Every
// method has both: the tests assert kKindsAsked keys, as a missing one would make their loops check less.
constexpr std::size_t kKindsAsked = 2;
std::vector<std::string> keys_of(const PickedVariants& picked) {
  std::vector<std::string> keys;
  for (int kind : {0, 1})
    if (picked.keys.count(kind)) keys.push_back(picked.keys.at(kind));
  return keys;
}

// Mean visibility at floor points around the foot of a pole 0.2 R thick and 2 R high at (0, -1), between
// 0.2 R and 0.45 R from its axis on the sides the camera sees.
double floor_around_pole(render::Backend& backend, const PickedVariants& picked, const std::string& key,
                         const render::ParamOverrides& params) {
  auto view = floor_view();
  auto plan = render::plan_pipeline(picked.compiled, variant_index(picked.compiled, key),
                                    target_of("lavapipe"), params);
  auto img = render_plan(backend, plan, view, kSize, kRadius, 2);
  double sum = 0;
  int n = 0;
  for (float d : {0.2f, 0.3f, 0.45f})
    for (glm::vec3 p : {glm::vec3{d * kRadius, 0, -1}, glm::vec3{-d * kRadius, 0, -1}, glm::vec3{0, 0, -1 + d * kRadius}}) {
      glm::ivec2 px = project(view, kSize, p);
      sum += img.at(px.x, px.y), ++n;
    }
  return sum / n;
}

// lavapipe with the floor and the thin pole of floor_around_pole loaded.
std::unique_ptr<render::Backend> pole_backend() {
  std::vector<Quad> quads = pole(0.0f, -1.0f, 0.2f * kRadius, 2.0f * kRadius);
  quads.push_back(kFloor);
  auto backend = render::make_backend("lavapipe", {});
  backend->set_scene(quad_scene(quads, floor_view(), kRadius));
  return backend;
}

class ThinOccluder : public ::testing::TestWithParam<std::string> {};

TEST_P(ThinOccluder, CompensationLightensTheFloorAroundAThinPole) {
  auto picked = pick_variants(method_kinds(GetParam()));
  const auto keys = keys_of(picked);
  ASSERT_EQ(keys.size(), kKindsAsked) << "a plain or blurred variant of " << GetParam() << " is missing";
  auto backend = pole_backend();
  for (const auto& key : keys) {
    double off = floor_around_pole(*backend, picked, key, {});
    double on = floor_around_pole(*backend, picked, key, {{"ao.thin_occluder_compensation", 0.7}});
    // The pole shadows its foot, and compensation takes away at least a tenth of that shadow.
    EXPECT_LT(off, 0.97) << key << ": the pole should shadow its foot without compensation";
    EXPECT_LT(1.0 - on, 0.9 * (1.0 - off)) << key << ": compensation " << on << " vs off " << off;
  }
}

TEST_P(ThinOccluder, AThickWallStillDarkensItsContactWithCompensation) {
  auto picked = pick_variants(method_kinds(GetParam()));
  auto view = floor_view();
  auto sc = quad_scene({kFloor, kWall}, view, kRadius);
  glm::ivec2 pc = project(view, kSize, {0.0f, 0.0f, -2.0f + 0.1f * kRadius});
  glm::ivec2 po = project(view, kSize, {0.0f, 0.0f, -2.0f + 4.0f * kRadius});
  auto backend = render::make_backend("lavapipe", {});
  backend->set_scene(sc);
  const auto keys = keys_of(picked);
  ASSERT_EQ(keys.size(), kKindsAsked) << "a plain or blurred variant of " << GetParam() << " is missing";
  for (const auto& key : keys) {
    auto plan = render::plan_pipeline(picked.compiled, variant_index(picked.compiled, key), target_of("lavapipe"),
                                      {{"ao.thin_occluder_compensation", 0.7}});
    auto img = render_plan(*backend, plan, view, kSize, kRadius, 2);
    EXPECT_LT(img.at(pc.x, pc.y), img.at(po.x, po.y) - 0.1f) << key;
  }
}

INSTANTIATE_TEST_SUITE_P(Horizon, ThinOccluder, ::testing::Values("gtao", "hbao"),
                         [](const auto& info) { return info.param; });

// VBAO: the floor around the thin pole is lighter with a thin assumed thickness than with a thick one (a
// thickness of many radii is a horizon: everything below the pole's top is hidden).
TEST(VisibilityBitmask, ThinnerThicknessLightensTheFloorAroundAThinPole) {
  auto picked = pick_variants(method_kinds("vbao"));
  const auto keys = keys_of(picked);
  ASSERT_EQ(keys.size(), kKindsAsked) << "a plain or blurred VBAO variant is missing";
  auto backend = pole_backend();
  for (const auto& key : keys) {
    double thick = floor_around_pole(*backend, picked, key, {{"ao.thickness", 8.0}});
    double thin = floor_around_pole(*backend, picked, key, {{"ao.thickness", 0.1}});
    EXPECT_GT(thin, thick + 0.02) << key << ": thickness 0.1 " << thin << " vs 8 " << thick;
  }
}

}  // namespace
}  // namespace aovar::test
