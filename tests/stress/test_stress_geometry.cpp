// Stress geometry (issue 7): camera and scene configurations that break naive depth handling, through
// the real pipeline of every AO method on both backends. An infinite far plane (a finite, invertible
// projection; the G-buffer's background depth stays finite) and a 1e10 far/near ratio on the atrium; the
// built-in stress scenes builtin:degenerate (zero-area triangles, needle slivers, zero-length and
// cancelling normals, kept as they are by load_scene) and builtin:far (geometry 200-4000 units away, where
// r16f linear depth steps by 0.125-2 units). Passing means finite visibility in [0, 1] on every pixel; on
// builtin:far r16f must also differ measurably from r32f, more than on the atrium.
#include <gtest/gtest.h>

#include "image/health.h"


#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "measure/measure.h"
#include "render/frame.h"
#include "render_support.h"
#include "test_support.h"
#include "variants/manifest.h"

namespace aovar::test {
namespace {

const std::vector<std::string> kBackends = {"lavapipe", "osmesa"};

bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}
bool finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

scene::View atrium_overview(float near_plane, float far_plane) {
  scene::View v = scene::load_scene("builtin:atrium").view("overview");
  v.near_plane = near_plane;
  v.far_plane = far_plane;
  return v;
}

// ---- the projection ----

TEST(StressFrame, InfiniteFarPlaneGivesAFiniteInvertibleProjection) {
  const scene::View v = atrium_overview(0.1f, kInf);
  for (auto clip : {render::ClipDepth::zero_to_one, render::ClipDepth::minus_one_to_one}) {
    SCOPED_TRACE(clip == render::ClipDepth::zero_to_one ? "zero_to_one" : "minus_one_to_one");
    render::FrameSetup s;
    s.view = &v;
    render::FrameBlock b = render::make_frame_block(s, {320, 180}, {160, 90}, clip);
    ASSERT_TRUE(finite(b.proj));
    ASSERT_TRUE(finite(b.inv_proj));
    ASSERT_TRUE(finite(b.proj_info));
    ASSERT_TRUE(finite(b.clip));
    // The background depth (what linear depth clears to, and the shaders' clip.y) is finite: the largest
    // finite half float, representable in r16f as well as r32f.
    EXPECT_EQ(b.clip.x, 0.1f);
    EXPECT_EQ(b.clip.y, 65504.0f);
    glm::mat4 id = b.proj * b.inv_proj;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(id[c][r], c == r ? 1.0f : 0.0f, 1e-5f) << c << "," << r;
    // NDC depth rises from the near plane's value towards 1 and never reaches it; unprojecting gives the point back.
    const float lo = clip == render::ClipDepth::zero_to_one ? 0.0f : -1.0f;
    float previous = lo - 1.0f;
    for (float d : {0.1f, 1.0f, 30.0f, 1e3f, 1e5f}) {
      glm::vec4 c = b.proj * glm::vec4(0.3f * d, -0.2f * d, -d, 1.0f);
      float ndc_z = c.z / c.w;
      EXPECT_GE(ndc_z, lo - 1e-6f) << d;
      EXPECT_LT(ndc_z, 1.0f) << d;
      EXPECT_GT(ndc_z, previous) << d;
      previous = ndc_z;
      if (d <= 1e3f) {
        glm::vec4 p = b.inv_proj * (c / c.w);
        EXPECT_NEAR(p.z / p.w, -d, 1e-3f * d) << d;
        EXPECT_NEAR(p.x / p.w, 0.3f * d, 1e-3f * d) << d;
      }
    }
    // The limit of the finite projection: a far plane of 1e7 gives the same matrix to float precision,
    // and the same similar-triangles factors.
    scene::View big = v;
    big.far_plane = 1e7f;
    render::FrameBlock f = render::make_frame_block({&big, 0, false, 1.0f}, {320, 180}, {160, 90}, clip);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(b.proj[c][r], f.proj[c][r], 1e-5f) << c << "," << r;
    EXPECT_EQ(b.proj_info, f.proj_info);
    EXPECT_EQ(b.clip.w, f.clip.w);
  }
}

TEST(StressFrame, BackgroundDepthIsTheFarPlaneUpToTheLargestHalf) {
  for (auto [far_plane, want] : {std::pair{50.0f, 50.0f}, {65504.0f, 65504.0f}, {1e6f, 65504.0f}, {kInf, 65504.0f}}) {
    scene::View v = atrium_overview(1e-4f, far_plane);
    render::FrameBlock b = render::make_frame_block({&v, 0, true, 0.5f}, {64, 36}, {64, 36},
                                                    render::ClipDepth::zero_to_one);
    EXPECT_EQ(b.clip.y, want) << far_plane;
    EXPECT_TRUE(finite(b.inv_proj)) << far_plane;
  }
}

// ---- views files ----

std::string load_error(const std::filesystem::path& views) {
  try {
    scene::LoadOptions o;
    o.views_file = views;
    scene::load_scene("builtin:stairs", o);
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(StressViews, FarPlaneMayBeInfiniteInTomlAndJson) {
  TempDir dir;
  write_text(dir / "v.toml",
             "[[view]]\nname = \"overview\"\neye = [4, 3, 6]\ntarget = [0, 1, 1]\nnear = 0.1\nfar = inf\n");
  scene::LoadOptions o;
  o.views_file = dir / "v.toml";
  scene::Scene s = scene::load_scene("builtin:stairs", o);
  EXPECT_TRUE(std::isinf(s.view("overview").far_plane) && s.view("overview").far_plane > 0);
  EXPECT_EQ(s.view("overview").near_plane, 0.1f);

  // JSON has no infinity literal: the string "inf" stands for it.
  write_text(dir / "v.json",
             R"({"views": [{"name": "overview", "eye": [4, 3, 6], "target": [0, 1, 1], "far": "inf"}]})");
  o.views_file = dir / "v.json";
  s = scene::load_scene("builtin:stairs", o);
  EXPECT_TRUE(std::isinf(s.view("overview").far_plane) && s.view("overview").far_plane > 0);
  EXPECT_GT(s.view("overview").near_plane, 0.0f);  // fitted to the scene
}

TEST(StressViews, NonFinitePlanesAreOneLineErrorsWithFileAndLine) {
  TempDir dir;
  const std::string head = "[[view]]\nname = \"a\"\neye = [4, 3, 6]\ntarget = [0, 1, 1]\n";
  const std::string jhead = "{\"views\": [\n {\"name\": \"a\", \"eye\": [4, 3, 6], \"target\": [0, 1, 1],\n  ";
  struct Case {
    std::string file, text, want;
  };
  for (const Case& c : {
           Case{"v.toml", head + "far = -inf\n", "v.toml:5:1: error: view 'a': far -inf"},
           Case{"v.toml", head + "near = 0.1\nfar = -inf\n", "v.toml:6:1: error: view 'a': far -inf"},
           Case{"v.toml", head + "far = nan\n", "v.toml:5:1: error: view 'a': far nan"},
           Case{"v.toml", head + "near = nan\n", "v.toml:5:1: error: view 'a': near nan"},
           Case{"v.toml", head + "near = inf\nfar = inf\n", "v.toml:5:1: error: view 'a': near inf"},
           Case{"v.toml", head + "fov = nan\n", "v.toml:5:1: error: view 'a': fov nan"},
           Case{"v.json", jhead + "\"far\": \"-inf\"}]}", "v.json:3:3: error: 'far' must be a number or \"inf\""},
           Case{"v.json", jhead + "\"far\": \"infinite\"}]}", "v.json:3:3: error: 'far' must be a number or \"inf\""},
           Case{"v.json", jhead + "\"near\": \"inf\"}]}", "v.json:3:3: error: 'near' must be a number"},
       }) {
    write_text(dir / c.file, c.text);
    EXPECT_TRUE(one_line_error_with(load_error(dir / c.file), c.want));
  }
}

// ---- the stress scenes ----

// The names of a scene's first three views: every stress scene starts with an overview, a closeup and a view
// with background in its frame (fewer names when it has fewer views).
std::vector<std::string> leading_views(const scene::Scene& s) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < std::min<std::size_t>(s.views.size(), 3); ++i) names.push_back(s.views[i].name);
  return names;
}
const std::vector<std::string> kStressViews = {"overview", "closeup", "background"};

// Nearest hit of a ray with the scene's triangles (brute force; < 0: miss).
float cast(const scene::Scene& s, const glm::vec3& o, const glm::vec3& d) {
  float best = -1.0f;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    glm::vec3 a = s.positions[s.indices[3 * t]], e1 = s.positions[s.indices[3 * t + 1]] - a,
              e2 = s.positions[s.indices[3 * t + 2]] - a;
    glm::vec3 p = glm::cross(d, e2);
    float det = glm::dot(e1, p);
    if (std::fabs(det) < 1e-12f) continue;
    glm::vec3 q = glm::cross(o - a, e1);
    float u = glm::dot(o - a, p) / det, v = glm::dot(d, q) / det, h = glm::dot(e2, q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && h > 0 && (best < 0 || h < best)) best = h;
  }
  return best;
}

TEST(StressScenes, DegenerateKeepsItsBrokenTrianglesAndNormals) {
  scene::Scene s = scene::load_scene("builtin:degenerate");
  EXPECT_EQ(leading_views(s), kStressViews);
  int same_index = 0, same_point = 0, collinear = 0, slivers = 0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    std::uint32_t i[3] = {s.indices[3 * t], s.indices[3 * t + 1], s.indices[3 * t + 2]};
    glm::vec3 a = s.positions[i[0]], b = s.positions[i[1]], c = s.positions[i[2]];
    float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    float area2 = glm::length(glm::cross(b - a, c - a));
    if (i[0] == i[1] && i[1] == i[2]) ++same_index;
    else if (a == b && b == c) ++same_point;
    else if (area2 == 0.0f) ++collinear;
    else if (area2 / (longest * longest) < 1e-3f) ++slivers;  // height under 1/500 of the length
  }
  EXPECT_GT(same_index, 0);
  EXPECT_GT(same_point, 0);
  EXPECT_GT(collinear, 0);
  EXPECT_GE(slivers, 4);
  // Zero-length normals survive load_scene (it renormalises the normals of every other scene), some on
  // whole triangles and some on a vertex shared with unit normals; other normals are unit length.
  int zero = 0, unit = 0;
  for (const glm::vec3& n : s.normals) {
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    if (n == glm::vec3(0.0f)) ++zero;
    else if (std::fabs(glm::length(n) - 1.0f) < 1e-4f) ++unit;
  }
  EXPECT_GE(zero, 4);
  EXPECT_EQ(zero + unit, static_cast<int>(s.normals.size()));
  int mixed = 0;  // triangles with a zero normal at some corners and a unit one at others
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    int z = 0;
    for (int k = 0; k < 3; ++k) z += s.normals[s.indices[3 * t + k]] == glm::vec3(0.0f);
    mixed += z == 1 || z == 2;
  }
  EXPECT_GT(mixed, 0);
  EXPECT_EQ(scene::load_scene("builtin:degenerate").content_hash, s.content_hash);
}

// Every surface a view sees lies 200-4000 units deep (view-space depth), and the background view leaves
// part of its frame empty: r16f linear depth there has steps of 0.125-2 units.
TEST(StressScenes, FarSceneIsSeenFrom200To4000Units) {
  scene::Scene s = scene::load_scene("builtin:far");
  EXPECT_EQ(leading_views(s), kStressViews);
  EXPECT_GE(s.ao_radius, 2.0f);
  EXPECT_LE(s.ao_radius, 50.0f);
  for (const scene::View& v : s.views) {
    SCOPED_TRACE(v.name);
    glm::vec3 f = glm::normalize(v.target - v.eye), r = glm::normalize(glm::cross(f, v.up)), u = glm::cross(r, f);
    float ty = std::tan(glm::radians(v.fov_y_deg) / 2), tx = ty * 16.0f / 9.0f;
    float lo = 1e30f, hi = 0.0f;
    int misses = 0, rays = 0;
    for (int j = 0; j < 18; ++j)
      for (int i = 0; i < 32; ++i, ++rays) {
        glm::vec3 d = glm::normalize(f + ((2.0f * i + 1) / 32 - 1) * tx * r + ((2.0f * j + 1) / 18 - 1) * ty * u);
        float t = cast(s, v.eye, d);
        if (t < 0 || t > v.far_plane) {
          ++misses;
          continue;
        }
        float depth = t * glm::dot(d, f);
        lo = std::min(lo, depth), hi = std::max(hi, depth);
      }
    EXPECT_GE(lo, 200.0f);
    EXPECT_LE(hi, 4000.0f);
    EXPECT_LT(misses, rays);
    if (v.name == "background") { EXPECT_GE(misses, rays / 5); }
  }
}

// ---- every method through both backends ----

std::vector<std::string> manifest_algorithms() {
  auto m = variants::load_manifest(source_dir() / "shader_src" / "aovar.toml");
  std::vector<std::string> out;
  for (const auto& v : m.axis_values(variants::Axis::algorithm)) out.push_back(v.text);
  return out;
}

// The variant kinds of tests/test_methods.cpp (each a list of globs in order of preference), plus the
// plain 8-sample variant on r16f depth for the r16f / r32f comparison.
enum Kind { kPlain, kBlurred, kProgressive, kPlainR16f, kKinds };

using MethodVariants = PickedVariants;

const MethodVariants& method_variants(const std::string& algorithm) {
  static std::map<std::string, MethodVariants> cache;
  auto it = cache.find(algorithm);
  if (it == cache.end()) {
    auto kinds = method_kinds(algorithm);
    const std::string a = algorithm + "-";
    kinds.push_back({a + "s08-p0-nrgb8-zdep-rst-d16-bno-x1-hp", a + "s08-p0-*-zdep-*-d16-bno-x1-??"});  // kPlainR16f (??: not -zmip)
    it = cache.emplace(algorithm, pick_variants(kinds)).first;
  }
  return it->second;
}

render::PipelinePlan plan_for(const MethodVariants& mv, const std::string& key, const std::string& backend) {
  return render::plan_pipeline(mv.compiled, variant_index(mv.compiled, key), target_of(backend));
}

// Renders every given kind of a method on each view through both backends and expects finite visibility
// in [0, 1] on every pixel.
void expect_healthy(const MethodVariants& mv, const std::vector<Kind>& kinds, const scene::Scene& sc,
                    const std::vector<scene::View>& views, float radius) {
  for (const auto& b : kBackends) {
    auto backend = render::make_backend(b, {});
    backend->set_scene(sc);
    for (Kind k : kinds) {
      auto key = mv.keys.find(k);
      ASSERT_NE(key, mv.keys.end()) << "no variant of kind " << k;
      auto plan = plan_for(mv, key->second, b);
      for (const auto& view : views) {
        auto img = render_plan(*backend, plan, view, {160, 90}, radius, 2);
        auto h = image::health(img);
        EXPECT_EQ(h.nan + h.inf + h.out_of_range, 0)
            << b << " " << key->second << " " << sc.name << "/" << view.name << " (near " << view.near_plane
            << ", far " << view.far_plane << "): " << h.nan << " NaN, " << h.inf << " Inf, " << h.out_of_range
            << " outside [0, 1]";
      }
    }
  }
}

class StressMethod : public ::testing::TestWithParam<std::string> {};

TEST_P(StressMethod, InfiniteFarAndExtremePlaneRatiosStayFinite) {
  const auto& mv = method_variants(GetParam());
  auto sc = scene::load_scene("builtin:atrium");
  scene::View infinite = atrium_overview(0.1f, kInf), ratio = atrium_overview(1e-4f, 1e6f);
  infinite.name = "overview(near 0.1, far inf)", ratio.name = "overview(near 1e-4, far 1e6)";
  expect_healthy(mv, {kPlain, kBlurred, kProgressive, kPlainR16f}, sc, {infinite, ratio}, sc.ao_radius);
}

TEST_P(StressMethod, DegenerateAndFarScenesStayFinite) {
  const auto& mv = method_variants(GetParam());
  for (const std::string name : {"builtin:degenerate", "builtin:far"}) {
    auto sc = scene::load_scene(name);
    expect_healthy(mv, {kPlain, kBlurred, kProgressive, kPlainR16f}, sc, sc.views, sc.ao_radius);
  }
}

// The far plane only decides what is background: the atrium (everything within 40 m) renders the same AO
// with an infinite far plane as with its fitted one. Both backends: a NaN projection would leave no
// geometry at all (all visibility 1), which the health check alone cannot see. With near 1e-4 and far 1e6
// the hardware depth test (D32F, ndc z = 1 - near / z) resolves only ~0.5 m at 30 m, so nearby surfaces
// may swap at some pixels, and inverse-projection reconstruction (rip) rebuilds ndc z from linear depth
// with the same cancellation (measured mean 0.05-0.1 off for alchemy's rip variant; printed, not asserted);
// the similar-triangles variants stay within 0.02 on average.
TEST_P(StressMethod, InfiniteFarRendersLikeTheFittedFar) {
  const auto& mv = method_variants(GetParam());
  auto sc = scene::load_scene("builtin:atrium");
  const scene::View fitted = sc.view("overview");
  const scene::View infinite = atrium_overview(fitted.near_plane, kInf), ratio = atrium_overview(1e-4f, 1e6f);
  for (const auto& b : kBackends) {
    auto backend = render::make_backend(b, {});
    backend->set_scene(sc);
    for (Kind k : {kPlain, kBlurred, kProgressive}) {
      const std::string& key = mv.keys.at(k);
      auto plan = plan_for(mv, key, b);
      auto base = render_plan(*backend, plan, fitted, {160, 90}, sc.ao_radius, 2);
      ImageDiff inf_diff = compare(render_plan(*backend, plan, infinite, {160, 90}, sc.ao_radius, 2), base);
      ImageDiff ratio_diff = compare(render_plan(*backend, plan, ratio, {160, 90}, sc.ao_radius, 2), base);
      std::printf("%s %s: far inf vs fitted mean %.5f max %.4f; near 1e-4 far 1e6 vs fitted mean %.5f max %.4f\n",
                  b.c_str(), key.c_str(), inf_diff.mean_abs, inf_diff.max_abs, ratio_diff.mean_abs, ratio_diff.max_abs);
      EXPECT_LE(inf_diff.mean_abs, 1e-3) << b << " " << key;
      EXPECT_LE(inf_diff.max_abs, 0.2) << b << " " << key;
      if (key.find("-rip-") == std::string::npos) { EXPECT_LE(ratio_diff.mean_abs, 0.02) << b << " " << key; }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Manifest, StressMethod, ::testing::ValuesIn(manifest_algorithms()),
                         [](const auto& info) { return info.param; });

// r16f against r32f, plain 8-sample variant of every method, lavapipe, 640x360 (the far scene's kernel
// is 1-7 pixels there). Float spacing and the templates' depth biases are both relative to depth, so what
// bands in r16f is a small radius for its depth, and the far scene's AO is faint (0.1-0.6 % occlusion on
// average): the measure is the r16f error as a share of the occlusion the r32f variant computes,
// mean |r16f - r32f| / mean (1 - r32f). Measured on lavapipe: 0.04-0.45 on builtin:far, 0.01-0.05 on the
// atrium but for SAO (0.40 there: its normals come from screen-space derivatives of positions, which r16f
// turns into terraces on camera-facing walls; 0.12 on builtin:far). Asserted, robustly: every method's
// r16f differs measurably on builtin:far (some pixel by 0.01 or more), and summed over the methods the share
// is larger on builtin:far than on the atrium (1.7 against 0.63).
TEST(StressDepthFormat, R16fBandsMoreOnTheFarSceneThanOnTheAtrium) {
  auto far_scene = scene::load_scene("builtin:far"), atrium = scene::load_scene("builtin:atrium");
  auto backend = render::make_backend("lavapipe", {});
  struct Measured {
    ImageDiff diff;
    double occlusion = 0, share = 0;
  };
  auto measure = [&](const MethodVariants& mv, const scene::Scene& sc) {
    backend->set_scene(sc);
    const scene::View& view = sc.view("overview");
    auto r16 = render_plan(*backend, plan_for(mv, mv.keys.at(kPlainR16f), "lavapipe"), view, {640, 360}, sc.ao_radius, 2);
    auto r32 = render_plan(*backend, plan_for(mv, mv.keys.at(kPlain), "lavapipe"), view, {640, 360}, sc.ao_radius, 2);
    Measured m;
    m.diff = compare(r16, r32);
    for (float v : r32.pixels) m.occlusion += 1.0 - v;
    m.occlusion /= static_cast<double>(r32.pixels.size());
    m.share = m.diff.mean_abs / std::max(m.occlusion, 1e-4);
    return m;
  };
  double far_total = 0, atrium_total = 0;
  for (const std::string& algorithm : manifest_algorithms()) {
    const auto& mv = method_variants(algorithm);
    ASSERT_TRUE(mv.keys.count(kPlain) && mv.keys.count(kPlainR16f)) << algorithm;
    Measured f = measure(mv, far_scene), a = measure(mv, atrium);
    std::printf("%-9s r16f vs r32f  builtin:far mean %.5f max %.4f occlusion %.4f share %.3f | "
                "builtin:atrium mean %.5f max %.4f occlusion %.4f share %.3f\n",
                algorithm.c_str(), f.diff.mean_abs, f.diff.max_abs, f.occlusion, f.share, a.diff.mean_abs,
                a.diff.max_abs, a.occlusion, a.share);
    EXPECT_GE(f.diff.max_abs, 0.01) << algorithm << ": r16f should differ measurably from r32f on builtin:far";
    far_total += f.share, atrium_total += a.share;
  }
  EXPECT_GT(far_total, atrium_total);
}

}  // namespace
}  // namespace aovar::test
