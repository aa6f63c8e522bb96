// What only the osmesa backend (OpenGL 4.5 core on llvmpipe) does (the contract every backend keeps:
// test_backend_contract.cpp): SAO's pyramid planned for a tiny target, a hand-made plan that pins down
// double-buffering and parameter blocks, the context's errors, and the GL objects a pipeline owns.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "render/backend.h"
#include "render/gl/gl_backends.h"
#include "render/gl/osmesa_internal.h"
#include "render/plan.h"
#include "render_support.h"
#include "scene/scene.h"
#include "test_support.h"

namespace aovar::render {
namespace {

const char* kOsmesaKey = "alchemy-s08-p1-ndep-zdep-rip-d16-bsep-x4-mp";
const test::CompiledVariants kOsmesaVariants({kOsmesaKey});

FrameSetup frame_of(const scene::View& view, int frame, float radius = test::kBoxRadius) {
  FrameSetup f;
  f.view = &view;
  f.frame = frame;
  f.static_camera = true;
  f.radius = radius;
  return f;
}

// SAO's six-level z pyramid at quarter resolution of 96x54 (24x14, five levels possible): the plan at that
// size keeps five levels and five pyramid draws. Before plan_for_size, OpenGL refused the texture storage
// (GL_INVALID_OPERATION) and lavapipe silently took an invalid image.
TEST(Osmesa, SaoPyramidFitsATinyTarget) {
  compile::CompileOptions o;
  o.scope.targets = {variants::Target::gl45};
  o.globs = {"sao-s12-p1-ndep-zdep-rst-d32-bbil-x4-hp"};
  auto c = compile::compile_space(aovar::test::on_manifest(o, std::filesystem::path(AOVAR_SOURCE_DIR) / "shader_src" / "aovar.toml"));
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
  scene::Scene sc = test::box_on_floor();
  backend->set_scene(sc);
  auto p = backend->prepare(plan, {96, 54});
  backend->render(*p, frame_of(sc.views.front(), 0, 1.0f));  // a radius of half the box: its contacts darken
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

TEST(Osmesa, DoubleBufferedTexturesAlternateByParityAndStartOpen) {
  // "write" puts frame + 1 + params[4] into copy `parity` of a double-buffered texture at AO resolution;
  // "combine" reads it as current (unit 5) and previous (unit 6): result = 100 current + previous + params[0].
  PipelinePlan plan;
  plan.variant = "test-parity";
  plan.resolution = 0.5;
  plan.shaders = {test::glsl_shader("fullscreen.vert", variants::StageKind::vertex, kFullscreenVert),
                  test::glsl_shader("write.frag", variants::StageKind::fragment, std::string("#version 450 core\n") + kFrameBlock + R"(
layout(std140, binding = 1) uniform AOParams { float a, b, c, d, e; } params;
void main() { o_color = vec4(float(frame.frame_index.x + 1) + params.e, 0.0, 0.0, 1.0); }
)"),
                  test::glsl_shader("combine.frag", variants::StageKind::fragment, std::string("#version 450 core\n") + kFrameBlock + R"(
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

TEST(Osmesa, FailedContextIsABackendError) {
  const std::string what = test::thrown_message<BackendError>([&] { osmesa::make_backend_with_version({}, 9, 9); });
  EXPECT_NE(what.find("4.5"), std::string::npos) << what;
  EXPECT_NE(what.find("libosmesa6"), std::string::npos) << what;
  // llvmpipe's thread count is fixed by the first context of the process; another one is refused.
  auto first = make_osmesa_backend({});
  BackendOptions three;
  three.threads = 3;
  EXPECT_THROW(make_osmesa_backend(three), BackendError);
}

TEST(Osmesa, PipelinesDeleteTheirObjectsAndOutliveTheirBackend) {
  auto backend = make_osmesa_backend({});
  scene::Scene sc = test::box_on_floor();
  backend->set_scene(sc);
  const scene::View& view = sc.views.front();
  PipelinePlan plan = kOsmesaVariants.plan(kOsmesaKey, "osmesa");
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
