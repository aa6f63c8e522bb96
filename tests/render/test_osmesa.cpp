// The osmesa backend (OpenGL 4.5 core on llvmpipe): real variants on a hand-built box-on-floor scene,
// hand-made plans that pin down double-buffering, parameter blocks and read-back, and the error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "render/backend.h"
#include "render/osmesa_internal.h"
#include "render/plan.h"
#include "render_support.h"
#include "scene/scene.h"

namespace aovar::render {
namespace {

// Every blur, resolution, normal encoding and position source, progressive, both depth formats, mediump.
const std::vector<std::string> kKeys = {
    "alchemy-s08-p0-nrg8-zdep-rst-d32-bno-x1-hp",
    "alchemy-s08-p0-nrgb8-zpos-rip-d16-bsep-x2-hp",
    "alchemy-s08-p1-noct-zdep-rst-d32-bbil-x1-hp",
    "alchemy-s08-p1-ndep-zdep-rip-d16-bsep-x4-mp",
};

const compile::CompiledSpace& space() {
  static const compile::CompiledSpace c = [] {
    compile::CompileOptions o;
    o.targets = {variants::Target::gl45};
    o.globs = kKeys;
    return compile::compile_space(std::filesystem::path(AOVAR_SOURCE_DIR) / "shader_src" / "aovar.toml", o);
  }();
  return c;
}

PipelinePlan plan_of(const std::string& key) {
  const auto& c = space();
  EXPECT_TRUE(c.ok()) << (c.diagnostics.empty() ? "" : c.diagnostics.front());
  for (std::size_t i = 0; i < c.space.variants.size(); ++i)
    if (c.space.variants[i].key == key) return plan_pipeline(c, static_cast<int>(i), variants::Target::gl45);
  ADD_FAILURE() << "no variant " << key;
  return {};
}

// A 16 x 16 floor (y = 0) with a 2 x 2 x 2 box standing on its centre, seen from the front and above;
// the top of the view shows background.
scene::Scene box_scene() {
  scene::Scene s;
  s.name = "test:box";
  s.source = "test";
  auto quad = [&](glm::vec3 corner, glm::vec3 u, glm::vec3 v) {  // normal u x v
    auto base = static_cast<std::uint32_t>(s.positions.size());
    glm::vec3 n = glm::normalize(glm::cross(u, v));
    for (glm::vec3 p : {corner, corner + u, corner + u + v, corner + v}) {
      s.positions.push_back(p);
      s.normals.push_back(n);
      s.bounds.extend(p);
    }
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) s.indices.push_back(base + i);
  };
  quad({-8, 0, 8}, {16, 0, 0}, {0, 0, -16});  // floor
  quad({-1, 0, 1}, {2, 0, 0}, {0, 2, 0});     // front (+z)
  quad({1, 0, -1}, {-2, 0, 0}, {0, 2, 0});    // back
  quad({1, 0, 1}, {0, 0, -2}, {0, 2, 0});     // right (+x)
  quad({-1, 0, -1}, {0, 0, 2}, {0, 2, 0});    // left
  quad({-1, 2, 1}, {2, 0, 0}, {0, 0, -2});    // top
  s.mesh_count = 6;
  s.ao_radius = 1.0f;
  scene::View v;
  v.name = "front";
  v.eye = {0.0f, 2.0f, 5.5f};
  v.target = {0.0f, 0.5f, 0.0f};
  v.fov_y_deg = 60.0f;
  v.near_plane = 0.1f;
  v.far_plane = 40.0f;
  v.path_offset = {0.0f, 0.0f, 0.0f};
  s.views = {v};
  return s;
}

// Pixel where a world point lands (row 0 = bottom), with the GL projection the backend uses.
glm::ivec2 project(const scene::View& view, Extent size, glm::vec3 world) {
  FrameSetup f;
  f.view = &view;
  FrameBlock b = make_frame_block(f, size, size, ClipDepth::minus_one_to_one);
  glm::vec4 clip = b.proj * b.view * glm::vec4(world, 1.0f);
  glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {static_cast<int>(std::floor((ndc.x * 0.5f + 0.5f) * size.width)),
          static_cast<int>(std::floor((ndc.y * 0.5f + 0.5f) * size.height))};
}

// Mean over a (2r+1)^2 window: single pixels of an unblurred variant carry the rotation pattern.
float window_mean(const image::FloatImage& img, glm::ivec2 c, int r = 2) {
  double sum = 0;
  int n = 0;
  for (int y = c.y - r; y <= c.y + r; ++y)
    for (int x = c.x - r; x <= c.x + r; ++x) {
      if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
      sum += img.at(x, y);
      ++n;
    }
  return n ? static_cast<float>(sum / n) : std::numeric_limits<float>::quiet_NaN();
}

FrameSetup frame_of(const scene::View& view, int frame, float radius = 1.0f) {
  FrameSetup f;
  f.view = &view;
  f.frame = frame;
  f.static_camera = true;
  f.radius = radius;
  return f;
}

TEST(Osmesa, DescribesAnOpenGL45CoreContextOnLlvmpipe) {
  auto b = make_osmesa_backend({});
  const DeviceInfo& d = b->info();
  EXPECT_EQ(d.backend, "osmesa");
  EXPECT_NE(d.device.find("llvmpipe"), std::string::npos) << d.device;
  EXPECT_EQ(d.api_version.rfind("OpenGL 4.5", 0), 0u) << d.api_version;
  EXPECT_EQ(d.driver.rfind("Mesa ", 0), 0u) << d.driver;
  EXPECT_GT(d.driver.size(), 5u);
  EXPECT_EQ(d.threads, 2);
  EXPECT_EQ(b->clip_depth(), ClipDepth::minus_one_to_one);
}

TEST(Osmesa, RendersOcclusionAtTheBoxAndNoneOnOpenFloor) {
  auto backend = make_osmesa_backend({});
  scene::Scene sc = box_scene();
  backend->set_scene(sc);
  const scene::View& view = sc.views.front();
  const Extent size{320, 180};
  glm::ivec2 corner = project(view, size, {0.0f, 0.0f, 1.12f});  // floor just in front of the box
  glm::ivec2 open = project(view, size, {-2.6f, 0.0f, 3.2f});     // 2.5 units from the box, radius 1
  glm::ivec2 sky{size.width / 2, size.height - 2};
  for (const auto& key : kKeys) {
    SCOPED_TRACE(key);
    PipelinePlan plan = plan_of(key);
    auto p = backend->prepare(plan, size);
    EXPECT_GT(p->create_ms, 0.0);
    for (int f = 0; f < 3; ++f) {
      std::vector<double> ms = backend->render(*p, frame_of(view, f));
      ASSERT_EQ(ms.size(), plan.draws.size());
      for (std::size_t i = 0; i < ms.size(); ++i) EXPECT_GT(ms[i], 0.0) << plan.draws[i].name;
    }
    image::FloatImage img = backend->read_result(*p);
    ASSERT_EQ(img.width, size.width);
    ASSERT_EQ(img.height, size.height);
    int bad = 0;
    for (float v : img.pixels) bad += !(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    EXPECT_EQ(bad, 0) << "pixels not finite or outside [0, 1]";
    float open_ao = window_mean(img, open), corner_ao = window_mean(img, corner);
    EXPECT_GE(open_ao, 0.95f);
    EXPECT_LT(corner_ao, open_ao - 0.15f) << "the box/floor contact must be darker than open floor";
    EXPECT_EQ(img.at(sky.x, sky.y), 1.0f) << "background (depth cleared to far) stays open";
  }
}

// SAO's six-level z pyramid at quarter resolution of 96x54 (24x14, five levels possible): the plan at that
// size keeps five levels and five pyramid draws. Before plan_for_size, OpenGL refused the texture storage
// (GL_INVALID_OPERATION) and lavapipe silently took an invalid image.
TEST(Osmesa, SaoPyramidFitsATinyTarget) {
  compile::CompileOptions o;
  o.targets = {variants::Target::gl45};
  o.globs = {"sao-s12-p1-ndep-zdep-rst-d32-bbil-x4-hp"};
  auto c = compile::compile_space(std::filesystem::path(AOVAR_SOURCE_DIR) / "shader_src" / "aovar.toml", o);
  ASSERT_TRUE(c.ok() && c.space.variants.size() == 1u);
  const PipelinePlan plan = plan_pipeline(c, 0, variants::Target::gl45);
  auto zmip = [](const PipelinePlan& p) {
    int levels = 0, draws = 0;
    for (const Texture& t : p.textures)
      if (t.name == "zmip") levels = t.levels;
    for (const Draw& d : p.draws) draws += d.name.rfind("zmip.", 0) == 0;
    return std::pair{levels, draws};
  };
  EXPECT_EQ(zmip(plan), (std::pair{kZmipLevels, kZmipLevels}));
  EXPECT_EQ(zmip(plan_for_size(plan, {1280, 720})), (std::pair{kZmipLevels, kZmipLevels}));
  EXPECT_EQ(zmip(plan_for_size(plan, {96, 54})), (std::pair{5, 5}));
  EXPECT_EQ(plan_for_size(plan, {96, 54}).draws.size(), plan.draws.size() - 1);

  auto backend = make_osmesa_backend({});
  scene::Scene sc = box_scene();
  backend->set_scene(sc);
  auto p = backend->prepare(plan, {96, 54});
  backend->render(*p, frame_of(sc.views.front(), 0));
  image::FloatImage img = backend->read_result(*p);
  ASSERT_EQ(img.pixels.size(), 96u * 54u);
  int bad = 0, occluded = 0;
  for (float v : img.pixels) {
    bad += !(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    occluded += v < 0.9f;
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(occluded, 0);
}

TEST(Osmesa, ProgressiveAveragesThisHalfWithThePreviousOne) {
  auto backend = make_osmesa_backend({});
  scene::Scene sc = box_scene();
  backend->set_scene(sc);
  const scene::View& view = sc.views.front();
  PipelinePlan plan = plan_of("alchemy-s08-p1-noct-zdep-rst-d32-bbil-x1-hp");
  auto p = backend->prepare(plan, {160, 90});
  std::vector<image::FloatImage> frames;
  for (int f = 0; f < 3; ++f) {
    backend->render(*p, frame_of(view, f));
    frames.push_back(backend->read_result(*p));
  }
  // Frame 0's history starts open (1.0): every average is at least a half.
  float lo0 = 1.0f;
  for (float v : frames[0].pixels) lo0 = std::min(lo0, v);
  EXPECT_GE(lo0, 0.5f - 1e-6f);
  EXPECT_NE(frames[0].pixels, frames[1].pixels) << "consecutive frames must differ";
  // Static camera: frames 1 and 2 average the same two halves (odd of frame 1, even of frame 2).
  EXPECT_EQ(frames[1].pixels, frames[2].pixels);
  float lo1 = 1.0f;
  for (float v : frames[1].pixels) lo1 = std::min(lo1, v);
  EXPECT_LT(lo1, lo0) << "both real halves are darker than one half plus an open history";
}

// Hand-made plans: a fullscreen triangle and fragment shaders that write known numbers.
const char* kFullscreenVert = R"(#version 450 core
void main() {
    vec2 uv = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}
)";

const char* kFrameBlock = R"(
layout(std140, binding = 0) uniform AOFrame {
    mat4 view; mat4 proj; mat4 inv_proj; vec4 proj_info; vec4 uv_to_ndc;
    vec4 full_size; vec4 ao_size; vec4 clip; ivec4 frame_index;
} frame;
layout(location = 0) out vec4 o_color;
)";

Shader shader(const std::string& key, variants::StageKind stage, const std::string& glsl) {
  Shader s;
  s.program_key = key;
  s.stage = stage;
  s.glsl = glsl;
  return s;
}

Draw fullscreen(const std::string& name, int fragment, std::vector<std::pair<int, TextureRef>> inputs, int output,
                std::vector<float> params = {}, bool full_resolution = true) {
  Draw d;
  d.name = d.pass = name;
  d.vertex = 0;
  d.fragment = fragment;
  d.params = std::move(params);
  d.inputs = std::move(inputs);
  d.outputs = {TextureRef{output}};
  d.full_resolution = full_resolution;
  return d;
}

scene::View plain_view() {
  scene::View v;
  v.name = "plain";
  return v;
}

TEST(Osmesa, ReadBackKeepsRowOrderExactValuesNaNAndInf) {
  PipelinePlan plan;
  plan.variant = "test-readback";
  plan.shaders = {shader("fullscreen.vert", variants::StageKind::vertex, kFullscreenVert),
                  shader("pattern.frag", variants::StageKind::fragment,
                         std::string("#version 450 core\n") + kFrameBlock + test::kReadbackPatternMain)};
  plan.textures = {Texture{"result", Format::r32f}};
  plan.draws = {fullscreen("pattern", 1, {}, 0)};
  plan.result = 0;

  auto backend = make_osmesa_backend({});
  auto p = backend->prepare(plan, {37, 5});  // odd width: rows are not a multiple of 8 bytes
  EXPECT_THROW(backend->read_result(*p), BackendError) << "nothing rendered yet";
  scene::View view = plain_view();
  backend->render(*p, frame_of(view, 0));
  test::expect_readback_pattern(backend->read_result(*p), 37, 5);
}

TEST(Osmesa, DoubleBufferedTexturesAlternateByParityAndStartOpen) {
  // "write" puts frame + 1 + params[4] into copy `parity` of a double-buffered texture at AO resolution;
  // "combine" reads it as current (unit 5) and previous (unit 6): result = 100 current + previous + params[0].
  PipelinePlan plan;
  plan.variant = "test-parity";
  plan.resolution = 0.5;
  plan.shaders = {shader("fullscreen.vert", variants::StageKind::vertex, kFullscreenVert),
                  shader("write.frag", variants::StageKind::fragment, std::string("#version 450 core\n") + kFrameBlock + R"(
layout(std140, binding = 1) uniform AOParams { float a, b, c, d, e; } params;
void main() { o_color = vec4(float(frame.frame_index.x + 1) + params.e, 0.0, 0.0, 1.0); }
)"),
                  shader("combine.frag", variants::StageKind::fragment, std::string("#version 450 core\n") + kFrameBlock + R"(
layout(std140, binding = 1) uniform AOParams { float a; } params;
layout(binding = 5) uniform sampler2D current_tex;
layout(binding = 6) uniform sampler2D previous_tex;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy) / 2;  // AO texel under this full-resolution pixel
    o_color = vec4(100.0 * texelFetch(current_tex, p, 0).r + texelFetch(previous_tex, p, 0).r + params.a, 0.0, 0.0, 1.0);
}
)")};
  plan.textures = {Texture{"half", Format::r32f, false, true}, Texture{"result", Format::r32f}};
  plan.draws = {fullscreen("write", 1, {}, 0, {9, 9, 9, 9, 0.5f}, false),
                fullscreen("combine", 2, {{5, TextureRef{0}}, {6, TextureRef{0, true}}}, 1, {0.25f})};
  plan.result = 1;

  auto backend = make_osmesa_backend({});
  auto p = backend->prepare(plan, {16, 8});
  scene::View view = plain_view();
  const float expected[] = {100 * 1.5f + 1.0f + 0.25f,   // frame 0: history is the initial 1.0
                            100 * 2.5f + 1.5f + 0.25f,   // frame 1 reads frame 0's copy
                            100 * 3.5f + 2.5f + 0.25f};  // frame 2 overwrote copy 0, reads frame 1's
  for (int f = 0; f < 3; ++f) {
    backend->render(*p, frame_of(view, f));
    image::FloatImage img = backend->read_result(*p);
    for (float v : img.pixels) ASSERT_EQ(v, expected[f]) << "frame " << f;
  }
}

TEST(Osmesa, ShaderThatFailsToCompileNamesItsProgramKey) {
  PipelinePlan plan;
  plan.variant = "test-broken";
  plan.shaders = {shader("fullscreen.vert", variants::StageKind::vertex, kFullscreenVert),
                  shader("broken-key.frag", variants::StageKind::fragment,
                         "#version 450 core\nlayout(location = 0) out vec4 o;\nvoid main() { o = undefined_thing; }\n")};
  plan.textures = {Texture{"result", Format::r32f}};
  plan.draws = {fullscreen("broken", 1, {}, 0)};
  plan.result = 0;
  auto backend = make_osmesa_backend({});
  try {
    backend->prepare(plan, {8, 8});
    FAIL() << "expected BackendError";
  } catch (const BackendError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("broken-key.frag"), std::string::npos) << what;
    EXPECT_NE(what.find("undefined_thing"), std::string::npos) << what;  // the driver's log
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // The backend stays usable after a failed prepare.
  plan.shaders[1].glsl = std::string("#version 450 core\n") + kFrameBlock + "void main() { o_color = vec4(0.5); }\n";
  auto p = backend->prepare(plan, {8, 8});
  scene::View view = plain_view();
  backend->render(*p, frame_of(view, 0));
  EXPECT_EQ(backend->read_result(*p).at(3, 3), 0.5f);
}

TEST(Osmesa, FailedContextIsABackendError) {
  try {
    osmesa::make_backend_with_version({}, 9, 9);
    FAIL() << "expected BackendError";
  } catch (const BackendError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("4.5"), std::string::npos) << what;
    EXPECT_NE(what.find("libosmesa6"), std::string::npos) << what;
  }
  // llvmpipe's thread count is fixed by the first context of the process; another one is refused.
  auto first = make_osmesa_backend({});
  EXPECT_THROW(make_osmesa_backend({.threads = 3}), BackendError);
}

TEST(Osmesa, PipelinesDeleteTheirObjectsAndOutliveTheirBackend) {
  auto backend = make_osmesa_backend({});
  scene::Scene sc = box_scene();
  backend->set_scene(sc);
  const scene::View& view = sc.views.front();
  PipelinePlan plan = plan_of("alchemy-s08-p1-ndep-zdep-rip-d16-bsep-x4-mp");
  osmesa::GlNames names;
  for (int i = 0; i < 3; ++i) {
    auto p = backend->prepare(plan, {64, 36});
    backend->render(*p, frame_of(view, 0));
    names = osmesa::object_names(*p);
    EXPECT_EQ(osmesa::count_live(*backend, names), names.size() - names.shaders.size()) << "shaders go after linking";
  }
  EXPECT_GT(names.size(), 10u);
  EXPECT_EQ(osmesa::count_live(*backend, names), 0u);

  // Two contexts at once: each call makes its own current.
  auto other = make_osmesa_backend({});
  other->set_scene(sc);
  auto a = backend->prepare(plan, {64, 36});
  auto b = other->prepare(plan, {64, 36});
  backend->render(*a, frame_of(view, 0));
  other->render(*b, frame_of(view, 0));
  EXPECT_EQ(backend->read_result(*a).pixels, other->read_result(*b).pixels);
  EXPECT_THROW(backend->render(*b, frame_of(view, 0)), BackendError) << "a pipeline of another backend";

  // Destroyed before its pipeline: the pipeline keeps the context alive for its own clean-up.
  backend.reset();
  a.reset();
}

}  // namespace
}  // namespace aovar::render
