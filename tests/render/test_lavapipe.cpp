// The lavapipe backend on a hand-built scene (a box standing on a floor): AO where it must be, clean under
// the validation layer (synchronisation validation included) from prepare to teardown, progressive parity,
// clears and orientation, timestamps, scene replacement, and the errors a user can meet.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "compile/generate.h"
#include "render/backend.h"
#include "render/lavapipe.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

render::BackendOptions backend_options(int threads, bool validation, bool mediump_as_fp16 = false) {
  render::BackendOptions o;
  o.threads = threads;
  o.validation = validation;
  o.mediump_as_fp16 = mediump_as_fp16;
  return o;
}

// Baseline, then separable / bilateral blur, half and quarter resolution, r16f depth, mediump, every normal
// encoding, the position buffer, and progressive.
const std::vector<std::string> kKeys = {
    "alchemy-s08-p0-nrg8-zdep-rst-d32-bno-x1-hp",
    "alchemy-s08-p0-nrgb8-zdep-rip-d32-bsep-x2-hp",
    "alchemy-s08-p0-noct-zdep-rst-d16-bbil-x4-mp",
    "alchemy-s08-p0-ndep-zpos-rip-d16-bsep-x1-hp",
    "alchemy-s08-p1-nrg8-zdep-rst-d32-bsep-x1-hp",
    "sao-s08-p1-ndep-zdep-rst-d32-bsep-x2-hp",       // z MIP pyramid (per-level views), packed key in rgba8
    "unsharp-s08-p0-ndep-zdep-_r-d16-bbil-x1-hp",     // depth Gaussian prefilter at binding 7
};

const compile::CompiledSpace& compiled() {
  static const compile::CompiledSpace c = [] {
    compile::CompileOptions o;
    o.targets = {variants::Target::vulkan};
    o.globs = kKeys;
    auto c = compile::compile_space(source_dir() / "shader_src" / "aovar.toml", o);
    if (!c.ok()) throw std::runtime_error(c.diagnostics.empty() ? "compile failed" : c.diagnostics[0]);
    return c;
  }();
  return c;
}

render::PipelinePlan plan_of(const std::string& key) {
  return render::plan_pipeline(compiled(), variant_index(compiled(), key), variants::Target::vulkan);
}

// A 2 x 2 x 2 box standing on a 20 x 20 floor, seen from the front, slightly from the right and above.
constexpr float kRadius = 0.5f;
scene::View box_view(float far_plane = 50.0f) {
  scene::View v;
  v.name = "box";
  v.eye = {2.0f, 2.5f, 6.0f};
  v.target = {0.0f, 0.5f, 0.0f};
  v.near_plane = 0.1f;
  v.far_plane = far_plane;
  return v;
}
const Quad kSmallFloor{{-10, 0, 10}, {20, 0, 0}, {0, 0, -20}};
const std::vector<Quad> kBox = {
    {{-1, 0, 1}, {2, 0, 0}, {0, 2, 0}},   // front (+z)
    {{1, 0, -1}, {-2, 0, 0}, {0, 2, 0}},  // back
    {{1, 0, 1}, {0, 0, -2}, {0, 2, 0}},   // right (+x)
    {{-1, 0, -1}, {0, 0, 2}, {0, 2, 0}},  // left
    {{-1, 2, 1}, {2, 0, 0}, {0, 0, -2}},  // top
};
scene::Scene box_scene() {
  std::vector<Quad> quads = kBox;
  quads.push_back(kSmallFloor);
  return quad_scene(quads, box_view(), kRadius);
}

render::FrameSetup frame_setup(const scene::View& view, int frame) {
  render::FrameSetup s;
  s.view = &view;
  s.frame = frame;
  s.static_camera = true;
  s.radius = kRadius;
  return s;
}

bool inside(glm::ivec2 p, render::Extent size) {
  return p.x >= 0 && p.y >= 0 && p.x < size.width && p.y < size.height;
}

void expect_sane(const image::FloatImage& img, render::Extent size, const std::string& what) {
  ASSERT_EQ(img.width, size.width) << what;
  ASSERT_EQ(img.height, size.height) << what;
  ASSERT_EQ(img.pixels.size(), std::size_t(size.width) * size.height) << what;
  int bad = 0;
  for (float v : img.pixels) bad += !(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
  EXPECT_EQ(bad, 0) << what << ": non-finite or out-of-range pixels";
}

// Open floor (far from the box) stays open; the floor at the foot of the box's front face is darker.
void expect_box_occlusion(const image::FloatImage& img, render::Extent size, const std::string& what) {
  scene::View view = box_view();
  glm::ivec2 open = project(view, size, {-3.0f, 0.0f, 3.5f});
  glm::ivec2 corner = project(view, size, {0.3f, 0.0f, 1.0f + 0.1f * kRadius});
  ASSERT_TRUE(inside(open, size) && inside(corner, size));
  EXPECT_GE(img.at(open.x, open.y), 0.95f) << what << ": open floor";
  EXPECT_LT(img.at(corner.x, corner.y), img.at(open.x, open.y) - 0.1f) << what << ": box/floor contact";
}

TEST(Lavapipe, ReportsTheCpuDevice) {
  auto backend = render::make_lavapipe_backend(backend_options(3, false));
  const auto& info = backend->info();
  EXPECT_EQ(info.backend, "lavapipe");
  EXPECT_NE(info.device.find("llvmpipe"), std::string::npos) << info.device;
  EXPECT_EQ(info.api_version.rfind("Vulkan 1.3.", 0), 0u) << info.api_version;
  EXPECT_NE(info.driver.find("Mesa"), std::string::npos) << info.driver;
  EXPECT_EQ(info.threads, 3);
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "3");
  EXPECT_EQ(backend->clip_depth(), render::ClipDepth::zero_to_one);
}

int process_threads() {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) n += entry.exists();
  return n;
}

// LP_NUM_THREADS is read per backend: more threads asked, more rasteriser threads running.
TEST(Lavapipe, ThreadCountTakesEffectPerBackend) {
  int one = 0, four = 0;
  {
    auto backend = render::make_lavapipe_backend(backend_options(1, false));
    one = process_threads();
  }
  {
    auto backend = render::make_lavapipe_backend(backend_options(4, false));
    four = process_threads();
  }
  EXPECT_GE(four, one + 3);
}

// Every variant of kKeys renders sane AO under the validation layer, and prepare, frames, read-back and
// teardown (pipelines, then the backend: leaked objects are reported at device destruction) report nothing.
TEST(Lavapipe, VariantsRenderAoCleanUnderValidation) {
  int errors_before = render::lavapipe_validation_error_count();
  const render::Extent size{160, 90};
  scene::View view = box_view();
  {
    auto backend = render::make_lavapipe_backend(backend_options(2, true));
    backend->set_scene(box_scene());
    for (const auto& key : kKeys) {
      auto plan = plan_of(key);
      auto pipeline = backend->prepare(plan, size);
      EXPECT_GT(pipeline->create_ms, 0.0) << key;
      for (int f = 0; f < 3; ++f) {
        auto times = backend->render(*pipeline, frame_setup(view, f));
        ASSERT_EQ(times.size(), plan.draws.size()) << key;
        for (std::size_t d = 0; d < times.size(); ++d) EXPECT_GT(times[d], 0.0) << key << " " << plan.draws[d].name;
      }
      auto img = backend->read_result(*pipeline);
      expect_sane(img, size, key);
      expect_box_occlusion(img, size, key);
    }
  }
  EXPECT_EQ(render::lavapipe_validation_error_count(), errors_before);
}

TEST(Lavapipe, ProgressiveFramesAlternateAndSettle) {
  const render::Extent size{160, 90};
  scene::View view = box_view();
  auto backend = render::make_lavapipe_backend(backend_options(2, false));
  backend->set_scene(box_scene());
  const std::string key = "alchemy-s08-p1-nrg8-zdep-rst-d32-bsep-x1-hp";
  auto pipeline = backend->prepare(plan_of(key), size);
  std::vector<image::FloatImage> frames;
  for (int f = 0; f < 6; ++f) {
    backend->render(*pipeline, frame_setup(view, f));
    frames.push_back(backend->read_result(*pipeline));
    expect_sane(frames.back(), size, "frame " + std::to_string(f));
  }
  // Frame 0 averages its half with the open (1.0) history; from frame 1 on both halves are real.
  EXPECT_GT(compare(frames[0], frames[1]).mean_abs, 1e-3) << "frame 0 history starts open";
  // Static camera: frame f + 1 averages the same two halves as frame f in the other roles (a + b = b + a
  // exactly); same-parity frames are identical too.
  EXPECT_EQ(compare(frames[4], frames[5]).max_abs, 0.0);
  EXPECT_EQ(compare(frames[3], frames[5]).max_abs, 0.0);
  EXPECT_EQ(compare(frames[2], frames[4]).max_abs, 0.0);
  expect_box_occlusion(frames[5], size, key);

  // The raw AO pass: parity 0 and 1 evaluate different halves of the kernel.
  auto half = backend->prepare(render::plan_prefix(plan_of(key), "ao"), size);
  backend->render(*half, frame_setup(view, 0));
  auto even = backend->read_result(*half);
  backend->render(*half, frame_setup(view, 1));
  auto odd = backend->read_result(*half);
  EXPECT_GT(compare(even, odd).mean_abs, 1e-3);
}

// The G-buffer's linear depth: cleared to the view's far plane (re-recorded when it changes), and row 0 of
// the read-back is the bottom of the view (the floor in front of the camera is nearer than the top rows).
TEST(Lavapipe, DepthClearFollowsFarPlaneAndRowZeroIsTheBottom) {
  const render::Extent size{160, 90};
  auto backend = render::make_lavapipe_backend(backend_options(2, false));
  // The floor alone, looked at from above: the top rows look past its far edge into the background.
  scene::View near_view = box_view(40.0f), far_view = box_view(80.0f);
  backend->set_scene(quad_scene({kSmallFloor}, near_view, kRadius));
  auto pipeline = backend->prepare(render::plan_prefix(plan_of(kKeys[0]), "gbuffer"), size);
  for (const auto* view : {&near_view, &far_view, &near_view}) {
    backend->render(*pipeline, frame_setup(*view, 0));
    auto depth = backend->read_result(*pipeline);
    EXPECT_FLOAT_EQ(depth.at(size.width / 2, size.height - 1), view->far_plane) << "background = far";
    float bottom = depth.at(size.width / 2, 0), middle = depth.at(size.width / 2, size.height / 2);
    EXPECT_GT(bottom, view->near_plane);
    EXPECT_LT(bottom, middle) << "row 0 must be the bottom of the view (nearest floor)";
  }
}

TEST(Lavapipe, TimestampsTimeEachDrawWithinTheFrame) {
  const render::Extent size{320, 180};
  scene::View view = box_view();
  auto backend = render::make_lavapipe_backend(backend_options(2, false));
  backend->set_scene(box_scene());
  auto plan = plan_of("alchemy-s08-p0-nrgb8-zdep-rip-d32-bsep-x2-hp");
  auto pipeline = backend->prepare(plan, size);
  backend->render(*pipeline, frame_setup(view, 0));  // JIT warm-up
  double best_ratio = 0;
  for (int f = 1; f < 8; ++f) {
    auto start = std::chrono::steady_clock::now();
    auto times = backend->render(*pipeline, frame_setup(view, f));
    double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    double sum = 0;
    for (double t : times) {
      EXPECT_GT(t, 0.0);
      sum += t;
    }
    // The stamps are taken between submit and fence, on the same clock: the draws fit in the frame's wall time.
    EXPECT_LE(sum, wall * 1.01 + 0.05);
    best_ratio = std::max(best_ratio, sum / wall);
  }
  // ...and cover most of it (the rest is submit, barriers and wake-ups; the best frame escapes the noise).
  EXPECT_GT(best_ratio, 0.5);
}

TEST(Lavapipe, SetSceneReplacesTheGeometryOfPreparedPipelines) {
  const render::Extent size{160, 90};
  scene::View view = box_view();
  auto backend = render::make_lavapipe_backend(backend_options(2, false));
  backend->set_scene(box_scene());
  auto pipeline = backend->prepare(plan_of(kKeys[0]), size);
  backend->render(*pipeline, frame_setup(view, 0));
  expect_box_occlusion(backend->read_result(*pipeline), size, "box");
  backend->set_scene(quad_scene({kSmallFloor}, view, kRadius));
  backend->render(*pipeline, frame_setup(view, 1));
  auto floor_only = backend->read_result(*pipeline);
  float lo = 1;
  for (float v : floor_only.pixels) lo = std::min(lo, v);
  EXPECT_GE(lo, 0.95f) << "the box must be gone";
}

TEST(Lavapipe, PipelinesMayOutliveTheirBackend) {
  int errors_before = render::lavapipe_validation_error_count();
  std::unique_ptr<render::PreparedPipeline> pipeline;
  {
    auto backend = render::make_lavapipe_backend(backend_options(2, true));
    backend->set_scene(box_scene());
    pipeline = backend->prepare(plan_of(kKeys[0]), {64, 36});
    backend->render(*pipeline, frame_setup(box_view(), 0));
  }
  pipeline.reset();  // releases its objects, then the device
  EXPECT_EQ(render::lavapipe_validation_error_count(), errors_before);
}

TEST(Lavapipe, MisuseThrowsBackendError) {
  auto backend = render::make_lavapipe_backend(backend_options(2, false));
  auto other = render::make_lavapipe_backend(backend_options(2, false));
  auto plan = plan_of(kKeys[0]);
  scene::View view = box_view();
  auto pipeline = backend->prepare(plan, {32, 18});
  EXPECT_THROW(backend->read_result(*pipeline), render::BackendError);         // nothing rendered yet
  EXPECT_THROW(backend->render(*pipeline, frame_setup(view, 0)), render::BackendError);  // no scene
  backend->set_scene(box_scene());
  EXPECT_THROW(other->render(*pipeline, frame_setup(view, 0)), render::BackendError);  // another backend
  EXPECT_THROW(backend->prepare(plan, {0, 18}), render::BackendError);
  scene::Scene broken = box_scene();
  broken.indices.push_back(99999);
  broken.indices.push_back(0);
  broken.indices.push_back(1);
  EXPECT_THROW(backend->set_scene(broken), render::BackendError);
}

TEST(Lavapipe, RejectedShaderNamesItsProgramAndLeavesTheBackendUsable) {
  auto backend = render::make_lavapipe_backend(backend_options(2, false));
  backend->set_scene(box_scene());
  auto plan = plan_of(kKeys[0]);
  const render::Shader& ao = plan.shaders[plan.draws[1].fragment];
  auto broken = plan;
  broken.shaders[plan.draws[1].fragment].spirv[0] = 0x12345678;  // not SPIR-V
  try {
    backend->prepare(broken, {32, 18});
    FAIL() << "expected BackendError";
  } catch (const render::BackendError& e) {
    EXPECT_NE(std::string(e.what()).find(ao.program_key), std::string::npos) << e.what();
  }
  broken.shaders[plan.draws[1].fragment].spirv.clear();
  EXPECT_THROW(backend->prepare(broken, {32, 18}), render::BackendError);
  auto pipeline = backend->prepare(plan, {32, 18});
  EXPECT_NO_THROW(backend->render(*pipeline, frame_setup(box_view(), 0)));
}

TEST(Lavapipe, MissingDriverOrLayerGivesAOneLineHint) {
  {
    ScopedEnv env;
    env.set("VK_ICD_FILENAMES", "/nonexistent/aovar_lvp_icd.json");
    env.set("VK_DRIVER_FILES", "/nonexistent/aovar_lvp_icd.json");
    try {
      render::make_lavapipe_backend(backend_options(2, false));
      FAIL() << "expected BackendError";
    } catch (const render::BackendError& e) {
      std::string m = e.what();
      EXPECT_NE(m.find("mesa-vulkan-drivers"), std::string::npos) << m;
      EXPECT_NE(m.find("scripts/deps"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  {
    ScopedEnv env;  // explicit layers are searched in VK_LAYER_PATH alone when it is set
    env.set("VK_LAYER_PATH", "/nonexistent/aovar_layers");
    env.set("VK_ADD_LAYER_PATH", "/nonexistent/aovar_layers");
    try {
      render::make_lavapipe_backend(backend_options(2, true));
      FAIL() << "expected BackendError";
    } catch (const render::BackendError& e) {
      std::string m = e.what();
      EXPECT_NE(m.find("VK_LAYER_KHRONOS_validation"), std::string::npos) << m;
      EXPECT_NE(m.find("vulkan-validationlayers"), std::string::npos) << m;
    }
  }
  // Restored: the driver and the layer are found again.
  EXPECT_NO_THROW(render::make_lavapipe_backend(backend_options(2, true)));
}

}  // namespace
}  // namespace aovar::test
