// The ray-traced reference: analytic cases (open plane, floor next to a wall), convergence with the ray
// count, the cache, obscurance against occlusion, the rasteriser's background, and the CLI's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <numbers>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "reference/cache.h"
#include "reference/detail.h"
#include "reference/reference.h"
#include "reference/sampling.h"
#include "render/frame.h"
#include "util/fs.h"
#include "util/verified_cache.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

namespace fs = std::filesystem;

// Primary ray of pixel (x, y) computed independently of src/reference: unproject the pixel centre through
// the inverse projection of the rasteriser's frame block.
struct Ray {
  glm::vec3 origin, dir;  // dir normalised
  glm::vec3 forward;      // view axis
};
Ray pixel_ray(const scene::View& view, render::Extent size, int x, int y) {
  render::FrameSetup s;
  s.view = &view;
  auto b = render::make_frame_block(s, size, size, render::ClipDepth::zero_to_one);
  glm::vec2 ndc{(x + 0.5f) / size.width * 2.0f - 1.0f, (y + 0.5f) / size.height * 2.0f - 1.0f};
  glm::vec4 p = b.inv_proj * glm::vec4(ndc, 0.5f, 1.0f);
  glm::mat4 inv_view = glm::inverse(b.view);
  glm::vec3 eye = glm::vec3(inv_view[3]);
  glm::vec3 world = glm::vec3(inv_view * glm::vec4(glm::vec3(p) / p.w, 1.0f));
  return {eye, glm::normalize(world - eye), -glm::vec3(inv_view[2])};
}

// Where pixel (x, y) meets the plane y = 0 (false when it looks up).
bool floor_point(const scene::View& view, render::Extent size, int x, int y, glm::vec3& hit, float& depth) {
  Ray r = pixel_ray(view, size, x, y);
  if (r.dir.y >= 0) return false;
  float t = -r.origin.y / r.dir.y;
  hit = r.origin + t * r.dir;
  depth = glm::dot(hit - r.origin, r.forward);
  return true;
}

reference::ReferenceOptions options(render::Extent size, float radius, int rays) {
  reference::ReferenceOptions o;
  o.size = size;
  o.radius = radius;
  o.rays = rays;
  o.threads = 2;
  return o;
}

// The cache tests' case: the floor with a low wall (half a unit high) across it (radius 1), seen from floor_view, traced at
// `size` with `rays` into the cache at `dir`.
struct LowWallCase {
  scene::View view;
  scene::Scene scene;
  reference::ReferenceOptions options;
};
LowWallCase cached_low_wall(const TempDir& dir, render::Extent size, int rays) {
  LowWallCase c{floor_view(), {}, options(size, 1.0f, rays)};
  c.scene = quad_scene({kFloor, {{-20.0f, 0.0f, -2.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 0.5f, 0.0f}}}, c.view, 1.0f);
  c.options.cache_dir = dir.path();
  return c;
}

// Cosine-weighted visibility of a point on an infinite floor at distance d = a R from an infinite wall.
double wall_visibility(double a) { return 1.0 - (std::acos(a) - a * std::sqrt(1.0 - a * a)) / std::numbers::pi; }


TEST(Reference, SobolPrefixIsStratifiedInEveryElementaryInterval) {
  // 16 points: every box of area 1/16 with power-of-two sides (1x16, 2x8, 4x4, 8x2, 16x1) holds one.
  for (int cols = 1; cols <= 16; cols *= 2) {
    int rows = 16 / cols;
    std::vector<int> count(16, 0);
    for (std::uint32_t i = 0; i < 16; ++i) {
      glm::vec2 p = reference::detail::sobol2(i);
      ASSERT_TRUE(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f) << i;
      ++count[static_cast<int>(p.y * rows) * cols + static_cast<int>(p.x * cols)];
    }
    for (int c : count) EXPECT_EQ(c, 1) << cols << " x " << rows;
  }
  // Neighbouring pixels get unrelated rotations.
  glm::vec2 a = reference::detail::pixel_shift(10, 10), b = reference::detail::pixel_shift(11, 10),
            c = reference::detail::pixel_shift(10, 11);
  EXPECT_GT(glm::length(a - b), 1e-3f);
  EXPECT_GT(glm::length(a - c), 1e-3f);
}

TEST(Reference, OpenPlaneIsFullyVisibleAndCoversTheViewWhereItShould) {
  const render::Extent size{96, 54};
  const scene::View view = floor_view();
  auto sc = quad_scene({kFloor}, view, 1.0f);
  auto ref = reference::trace_reference(sc, view, options(size, 1.0f, 64));
  int surface = 0, background = 0, checked = 0;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * size.width + x;
      // Where the plane is, exactly 1: no hemisphere ray may hit the plane it starts on.
      EXPECT_EQ(ref.visibility.pixels[i], 1.0f) << x << "," << y;
      if (!ref.background[i]) {
        EXPECT_EQ(ref.std_error.pixels[i], 0.0f) << x << "," << y;
      }
      (ref.background[i] ? background : surface)++;
      glm::vec3 p;
      float depth = 0;
      bool on_floor = floor_point(view, size, x, y, p, depth);
      // Pixels whose floor point is within 0.3 of the quad's edge or 1 % of the background depth are
      // silhouettes: either answer is right there.
      float margin = on_floor ? std::min({20.0f - std::abs(p.x), 20.0f - std::abs(p.z),
                                          (view.far_plane * 0.999f - depth) / view.far_plane * 100.0f})
                              : -1.0f;
      if (std::abs(margin) < 0.3f) continue;
      ++checked;
      EXPECT_EQ(ref.background[i] != 0, margin < 0) << x << "," << y << " floor point " << p.x << "," << p.z;
    }
  EXPECT_GT(surface, size.width * size.height / 2);
  EXPECT_GT(background, 0) << "the top rows look past the floor's far edge";
  EXPECT_GT(checked, size.width * size.height * 9 / 10);
}

TEST(Reference, FloorNextToWallMatchesTheAnalyticVisibility) {
  const render::Extent size{128, 72};
  const float radius = 1.0f;
  const scene::View view = floor_view();
  auto sc = quad_scene({kFloor, kWall}, view, radius);
  auto ref = reference::trace_reference(sc, view, options(size, radius, 1024));
  int checked = 0;
  for (double wanted : {0.15, 0.4, 0.65, 0.9}) {
    glm::ivec2 px = project(view, size, {0.0f, 0.0f, -2.0f + static_cast<float>(wanted) * radius});
    glm::vec3 p;
    float depth;
    ASSERT_TRUE(floor_point(view, size, px.x, px.y, p, depth));
    const double a = (p.z + 2.0) / radius;  // the pixel centre's own distance from the wall
    ASSERT_TRUE(a > 0.0 && a < 1.0) << a;
    const std::size_t i = static_cast<std::size_t>(px.y) * size.width + px.x;
    ASSERT_FALSE(ref.background[i]);
    const double expected = wall_visibility(a), got = ref.visibility.pixels[i], se = ref.std_error.pixels[i];
    EXPECT_GT(se, 0.0) << "partly occluded: the rays disagree";
    EXPECT_NEAR(got, expected, 3.0 * se) << "a = " << a << " at pixel " << px.x << "," << px.y;
    // The reported error is conservative for the rotated Sobol set: the real error is far smaller.
    EXPECT_NEAR(got, expected, 0.01) << "a = " << a << " at pixel " << px.x << "," << px.y;
    ++checked;
    std::printf("  a = %.3f: visibility %.4f, analytic %.4f, |error| %.4f, std error %.4f\n", a, got, expected,
                std::abs(got - expected), se);
  }
  EXPECT_EQ(checked, 4);
}

TEST(Reference, ErrorFallsAtLeastAsFastAsOneOverSqrtRays) {
  auto sc = scene::load_scene("builtin:atrium");
  const scene::View& view = sc.views.front();
  auto o = options({48, 27}, sc.ao_radius, 4096);
  auto truth = reference::trace_reference(sc, view, o);
  std::vector<int> counts{16, 64, 256};
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int n : counts) {
    o.rays = n;
    double e = reference::surface_rmse(reference::trace_reference(sc, view, o), truth);
    ASSERT_GT(e, 0.0);
    std::printf("  %4d rays: rmse %.5f against 4096 rays\n", n, e);
    double x = std::log(double(n)), y = std::log(e);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double k = double(counts.size());
  const double slope = (k * sxy - sx * sy) / (k * sxx - sx * sx);
  std::printf("  slope of log rmse over log rays: %.3f\n", slope);
  EXPECT_LE(slope, -0.45);
}

// The reference's depth (for the error breakdown) is the primary rays' t, the same as trace_depth's; the cache
// keeps it with the image, bit for bit, without tracing again.
TEST(Reference, DepthIsTraceDepthsAndTheCacheKeepsIt) {
  TempDir dir;
  auto [view, sc, o] = cached_low_wall(dir, {32, 18}, 16);
  const auto traced = reference::trace_reference(sc, view, o);
  const auto depth = reference::trace_depth(sc, view, o.size).depth;
  ASSERT_EQ(traced.depth.pixels.size(), depth.pixels.size());
  EXPECT_EQ(std::memcmp(traced.depth.pixels.data(), depth.pixels.data(), depth.pixels.size() * sizeof(float)), 0);
  for (std::size_t i = 0; i < depth.pixels.size(); ++i)
    EXPECT_EQ(std::isinf(traced.depth.pixels[i]), traced.background[i] == 1) << "pixel " << i;

  ASSERT_TRUE(fs::is_regular_file(reference::detail::ReferenceCache(dir.path()).entry_path(traced.key)));
  const auto traces = reference::detail::trace_calls.load();
  const auto cached = reference::trace_reference(sc, view, o);
  EXPECT_TRUE(cached.from_cache);
  EXPECT_EQ(reference::detail::trace_calls.load(), traces) << "the hemisphere is not traced again";
  EXPECT_EQ(std::memcmp(cached.depth.pixels.data(), depth.pixels.data(), depth.pixels.size() * sizeof(float)), 0);
}

// Traces `o` once more after `damage` and checks what issue 54 asks of every cache: one warning line, traced
// again (not used), the answer bit-identical to `expected`, and the entry stored again whole.
void expect_traced_again(const scene::Scene& sc, const scene::View& view, const reference::ReferenceOptions& o,
                         const reference::ReferenceImage& expected, const std::string& damage) {
  SCOPED_TRACE(damage);
  const auto traces = reference::detail::trace_calls.load();
  testing::internal::CaptureStderr();
  const auto again = reference::trace_reference(sc, view, o);
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(has_text(warning, "a damaged reference cache entry: computing it again")) << warning;
  EXPECT_EQ(std::count(warning.begin(), warning.end(), '\n'), 1) << "one line: " << warning;
  EXPECT_FALSE(again.from_cache);
  EXPECT_EQ(reference::detail::trace_calls.load(), traces + 1);
  EXPECT_EQ(again.visibility.pixels, expected.visibility.pixels);
  EXPECT_EQ(again.std_error.pixels, expected.std_error.pixels);
  EXPECT_EQ(again.background, expected.background);
  EXPECT_TRUE(reference::trace_reference(sc, view, o).from_cache) << "stored again, whole";
}

// A damaged entry (cut short by a full disk or by hand, a flipped bit, another key's entry moved over it, a
// folder where it goes, another cache's entry) is traced again and replaced, with a warning on stderr; the
// cache is a speed-up, never a reason for a run to fail, never a different answer.
TEST(Reference, DamagedCacheEntryIsTracedAgainAndReplaced) {
  TempDir dir;
  auto [view, sc, o] = cached_low_wall(dir, {32, 18}, 16);
  const auto first = reference::trace_reference(sc, view, o);
  auto other_o = o;
  other_o.rays = 8;
  const auto other = reference::trace_reference(sc, view, other_o);
  const reference::detail::ReferenceCache cache(dir.path());
  const fs::path entry = cache.entry_path(first.key);
  const std::string whole = util::read_file(entry).value();

  util::write_atomic(entry, whole.substr(0, whole.size() / 2));
  expect_traced_again(sc, view, o, first, "truncated");
  std::string flipped = whole;
  flipped[flipped.size() - 5] ^= 0x10;
  util::write_atomic(entry, flipped);
  expect_traced_again(sc, view, o, first, "a flipped bit");
  util::write_atomic(entry, util::read_file(cache.entry_path(other.key)).value());
  expect_traced_again(sc, view, o, first, "another key's entry");
  fs::remove(entry);
  fs::create_directories(entry / "sub");
  expect_traced_again(sc, view, o, first, "a folder");
  const util::VerifiedCache traffic(dir.path(), "traffic");
  traffic.write("reference " + first.key, whole);
  util::write_atomic(entry, util::read_file(traffic.entry_path("reference " + first.key)).value());
  expect_traced_again(sc, view, o, first, "another cache's entry");
}

// Issue 54, reproduction 4: an entry of the right size full of NaN gave "rmse nan" and exit 0. Images with
// non-finite or out-of-range values are damaged like truncated ones even when their checksum is right (stored
// through the cache itself): traced again with a warning, and the answer is the traced one. The other members
// of the class: a visibility of 2, an Inf standard error, a NaN depth, an image of another size.
TEST(Reference, CacheEntryOfNonFiniteOrImpossibleValuesIsTracedAgain) {
  TempDir dir;
  auto [view, sc, o] = cached_low_wall(dir, {32, 18}, 16);
  const auto first = reference::trace_reference(sc, view, o);
  const reference::detail::ReferenceCache cache(dir.path());
  struct Damage {
    const char* what;
    void (*apply)(reference::ReferenceImage&);
  };
  const Damage damages[] = {
      {"visibility all NaN", [](reference::ReferenceImage& r) { std::fill(r.visibility.pixels.begin(), r.visibility.pixels.end(), kNaN); }},
      {"a visibility of 2", [](reference::ReferenceImage& r) { r.visibility.pixels[r.visibility.pixels.size() / 2] = 2.0f; }},
      {"an Inf standard error", [](reference::ReferenceImage& r) { r.std_error.pixels[r.std_error.pixels.size() / 2] = kInf; }},
      {"a NaN depth", [](reference::ReferenceImage& r) { r.depth.pixels[r.depth.pixels.size() / 2] = kNaN; }},
      {"another size", [](reference::ReferenceImage& r) {
         r.visibility.height = r.std_error.height = r.depth.height = r.visibility.height / 2;
         for (auto* img : {&r.visibility, &r.std_error, &r.depth}) img->pixels.resize(img->pixels.size() / 2);
         r.background.resize(r.background.size() / 2);
       }},
  };
  for (const Damage& d : damages) {
    reference::ReferenceImage bad = first;
    d.apply(bad);
    cache.store(first.key, bad);
    expect_traced_again(sc, view, o, first, d.what);
  }
}

// A cache folder that cannot be written (a file where it goes) warns once; the run goes on uncached with the
// uncached answer.
TEST(Reference, AnUnwritableCacheGoesOnUncached) {
  TempDir dir;
  const scene::View view = floor_view();
  auto sc = quad_scene({kFloor, kWall}, view, 1.0f);
  auto o = options({32, 18}, 1.0f, 16);
  const auto uncached = reference::trace_reference(sc, view, o);
  test::write_text(dir / "cache", "a file where the cache folder goes");
  o.cache_dir = dir / "cache";
  testing::internal::CaptureStderr();
  const auto traced = reference::trace_reference(sc, view, o);
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(has_text(warning, "the reference cache cannot be written")) << warning;
  EXPECT_EQ(traced.visibility.pixels, uncached.visibility.pixels);
  EXPECT_FALSE(reference::trace_reference(sc, view, o).from_cache);
}

TEST(Reference, CacheReturnsTheStoredImageBitIdenticalWithoutTracing) {
  TempDir dir;
  // A low wall: occlusion in front of it, and the background above the floor's far edge behind it.
  auto [view, sc, o] = cached_low_wall(dir, {64, 36}, 64);
  auto first = reference::trace_reference(sc, view, o);
  EXPECT_FALSE(first.from_cache);
  EXPECT_GT(first.rays_traced, 0u);
  EXPECT_TRUE(fs::is_regular_file(reference::detail::ReferenceCache(dir.path()).entry_path(first.key)));

  const auto traces = reference::detail::trace_calls.load();
  auto second = reference::trace_reference(sc, view, o);
  EXPECT_EQ(reference::detail::trace_calls.load(), traces) << "a cache hit must not trace";
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.rays_traced, 0u);
  EXPECT_EQ(second.trace_s, 0.0);
  EXPECT_EQ(second.key, first.key);
  ASSERT_EQ(second.visibility.pixels.size(), first.visibility.pixels.size());
  EXPECT_EQ(std::memcmp(second.visibility.pixels.data(), first.visibility.pixels.data(),
                        first.visibility.pixels.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(second.std_error.pixels.data(), first.std_error.pixels.data(),
                        first.std_error.pixels.size() * sizeof(float)), 0);
  EXPECT_EQ(second.background, first.background);
  int background = 0;
  for (auto b : second.background) background += b;
  EXPECT_GT(background, 0) << "the background survives the round trip (stored as std error -1)";

  // Every input is in the key: radius, rays, mode, frame, size and the view's camera path.
  auto key = [&](auto change) {
    auto o2 = o;
    scene::View v2 = view;
    change(o2, v2);
    return reference::cache_key(sc, v2, o2);
  };
  const std::string base = reference::cache_key(sc, view, o);
  EXPECT_EQ(base, first.key);
  EXPECT_NE(base, key([](auto& p, auto&) { p.radius = 1.5f; }));
  EXPECT_NE(base, key([](auto& p, auto&) { p.rays = 65; }));
  EXPECT_NE(base, key([](auto& p, auto&) { p.mode = reference::Mode::obscurance; }));
  EXPECT_NE(base, key([](auto& p, auto&) { p.frame = 3; }));
  EXPECT_NE(base, key([](auto& p, auto&) { p.size = {64, 37}; }));
  EXPECT_NE(base, key([](auto&, auto& v) { v.path_offset.x = 0.5f; }));
  EXPECT_NE(base, key([](auto&, auto& v) { v.fov_y_deg = 50.0f; }));
  EXPECT_EQ(base, key([](auto& p, auto&) { p.threads = 1; })) << "threads do not change the image";
}

TEST(Reference, ObscuranceIsNeverDarkerThanOcclusion) {
  const scene::View view = floor_view();
  auto sc = quad_scene({kFloor, kWall}, view, 1.5f);
  auto o = options({64, 36}, 1.5f, 64);
  auto occlusion = reference::trace_reference(sc, view, o);
  o.mode = reference::Mode::obscurance;
  auto obscurance = reference::trace_reference(sc, view, o);
  int brighter = 0;
  for (std::size_t i = 0; i < occlusion.visibility.pixels.size(); ++i) {
    EXPECT_GE(obscurance.visibility.pixels[i], occlusion.visibility.pixels[i]) << i;
    brighter += obscurance.visibility.pixels[i] > occlusion.visibility.pixels[i];
  }
  EXPECT_GT(brighter, 20) << "near the wall, hits at t > 0 occlude less than fully";
}

TEST(Reference, BackgroundMatchesTheRasterisersDepth) {
  // The G-buffer's linear depth through lavapipe: background where it reads >= 0.999 far (the AO passes'
  // ao_is_background). Masks must agree except at silhouette pixels (a neighbour differs).
  const render::Extent size{160, 90};
  auto sc = scene::load_scene("builtin:spheres");
  const scene::View& view = sc.view("background");
  const std::string key = "alchemy-s08-p0-nrgb8-zdep-rst-d32-bno-x1-hp";
  auto c = compile_variants({key});
  auto backend = render::make_backend("lavapipe", {});
  backend->set_scene(sc);
  auto plan = render::plan_prefix(render::plan_pipeline(c, variant_index(c, key), target_of("lavapipe")), "gbuffer");
  auto depth = render_plan(*backend, plan, view, size, sc.ao_radius, 1);
  auto ref = reference::trace_reference(sc, view, options(size, sc.ao_radius, 1));
  auto raster_bg = [&](int x, int y) { return depth.at(x, y) >= view.far_plane * 0.999f; };
  auto ref_bg = [&](int x, int y) { return ref.background[static_cast<std::size_t>(y) * size.width + x] != 0; };
  int mismatched = 0, silhouette = 0, bg = 0;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      bg += ref_bg(x, y);
      if (raster_bg(x, y) == ref_bg(x, y)) continue;
      bool edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int nx = std::clamp(x + dx, 0, size.width - 1), ny = std::clamp(y + dy, 0, size.height - 1);
          edge |= ref_bg(nx, ny) != ref_bg(x, y);
        }
      (edge ? silhouette : mismatched)++;
    }
  std::printf("  background %d of %d pixels; masks differ at %d silhouette pixels\n", bg, size.width * size.height,
              silhouette);
  EXPECT_EQ(mismatched, 0);
  EXPECT_LT(silhouette, size.width * size.height / 100);
  EXPECT_GT(bg, size.width * size.height / 5) << "the background view is 20-60 % empty";
  EXPECT_LT(bg, size.width * size.height * 3 / 5);
}

TEST(Reference, RadiusTextAndModeNames) {
  auto sc = scene::load_scene("builtin:spheres");
  EXPECT_FLOAT_EQ(reference::resolve_radius("0.25", sc), 0.25f);
  EXPECT_FLOAT_EQ(reference::resolve_radius("1.5%", sc), 0.015f * sc.bounds.diagonal());
  for (const char* bad : {"", "abc", "1.5%%", "-1", "0", "1.5 %", "2x"})
    EXPECT_THROW(reference::resolve_radius(bad, sc), std::invalid_argument) << bad;
  EXPECT_EQ(reference::parse_mode("obscurance"), reference::Mode::obscurance);
  EXPECT_STREQ(reference::mode_name(reference::Mode::occlusion), "occlusion");
  EXPECT_THROW(reference::parse_mode("ambient"), std::invalid_argument);
}

TEST(Reference, CliWritesImagesAndJson) {
  TempDir dir;
  auto r = run_aovar("reference --scene builtin:spheres --view background --view overview --size 64x36 --rays 8 "
                     "--radius 2% --no-cache --out " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"background.pfm", "background.stderr.pfm", "background.png", "overview.pfm", "reference.json"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  auto doc = nlohmann::json::parse(*util::read_file(dir / "out/reference.json"));
  EXPECT_EQ(doc["scene"], "builtin:spheres");
  ASSERT_EQ(doc["views"].size(), 2u);
  const auto& v = doc["views"][0];
  EXPECT_EQ(v["view"], "background");
  EXPECT_EQ(v["size"], "64x36");
  EXPECT_EQ(v["rays"], 8);
  EXPECT_EQ(v["mode"], "occlusion");
  EXPECT_GT(v["background_share"].get<double>(), 0.2);
  EXPECT_FALSE(v["from_cache"].get<bool>());
  EXPECT_GT(v["rays_per_s"].get<double>(), 0.0);
  EXPECT_EQ(v["files"]["visibility"], "background.pfm");
  auto loaded = reference::load_reference(dir / "out/background");
  EXPECT_EQ(loaded.visibility.width, 64);
}

TEST(Reference, CliBadInputGivesOneLineErrorAndExitTwo) {
  TempDir dir;
  const std::string out = " --no-cache --size 32x18 --out " + (dir / "out").string();
  struct Case {
    std::string args, needle;
  };
  for (const Case& c : std::vector<Case>{
           {"--scene builtin:spheres --view nope", "no view 'nope' (available: overview, closeup, background"},
           {"--scene builtin:spheres --radius abc", "--radius: radius 'abc': not a number"},
           {"--scene builtin:spheres --radius 1.5%x", "radius '1.5%x'"},
           {"--scene builtin:spheres --rays 0", "aovar reference: --rays: '0' is not a whole number from 1 to 65536"},
           {"--scene builtin:spheres --mode ambient", "--mode: unknown mode 'ambient' (use occlusion or obscurance)"},
           {"--scene " + (dir / "missing.obj").string(), "missing.obj"},
       }) {
    auto r = run_aovar("reference " + c.args + out);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << c.args;
  }
}

}  // namespace
}  // namespace aovar::test
