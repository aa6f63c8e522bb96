// The backend contract (render/backend.h), one suite run on every built-in backend (render/registry.cpp). Real
// variants of every buffer format, blur, resolution and precision render AO where it must be on a box standing
// on a floor; progressive frames alternate and settle; the depth clear follows the far plane and row 0 is the
// bottom; set_scene and set_params reach prepared pipelines; pipelines outlive their backend; misuse and a
// rejected shader are BackendErrors that leave the backend usable. The GL backends also read back exact
// floats (NaN and Inf included) from hand-written programs. What only one backend does (validation, timestamps,
// contexts, ES precision) is in test_lavapipe.cpp, test_osmesa.cpp and test_gles.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/plan.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const char* kContractBaseline = "alchemy-s08-p0-nrg8-zdep-rst-d32-bno-x1-hp";
const char* kContractProgressive = "alchemy-s08-p1-nrg8-zdep-rst-d32-bsep-x1-hp";
const CompiledVariants kContractVariants(backend_test_keys(), /*with_gles=*/true);

class BackendContract : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<render::Backend> make() const { return render::make_backend(GetParam(), {}); }
  render::PipelinePlan plan(const std::string& key) const { return kContractVariants.plan(key, GetParam()); }
};

TEST_P(BackendContract, DescribesItsLlvmpipeDevice) {
  struct Expected {
    const char* api_prefix;
    render::ClipDepth clip;
    variants::Target target;
  };
  const std::map<std::string, Expected> expected = {
      {"lavapipe", {"Vulkan 1.3.", render::ClipDepth::zero_to_one, variants::Target::vulkan}},
      {"osmesa", {"OpenGL 4.5", render::ClipDepth::minus_one_to_one, variants::Target::gl45}},
      {"gles", {"OpenGL ES 3.", render::ClipDepth::minus_one_to_one, variants::Target::gles30}},
  };
  const Expected& e = expected.at(GetParam());
  auto backend = make();
  const render::DeviceInfo& d = backend->info();
  EXPECT_EQ(d.backend, GetParam());
  EXPECT_TRUE(has_text(d.device, "llvmpipe")) << d.device;
  EXPECT_EQ(d.api_version.rfind(e.api_prefix, 0), 0u) << d.api_version;
  EXPECT_EQ(d.driver.rfind("Mesa ", 0), 0u) << d.driver;
  EXPECT_EQ(d.threads, render::BackendOptions{}.threads);
  EXPECT_FALSE(d.precision.empty());
  EXPECT_EQ(backend->clip_depth(), e.clip);
  EXPECT_EQ(render::target_of(GetParam()), e.target);
}

// Every contract variant renders sane AO with the occlusion where the box meets the floor, the background
// open, a time for every draw and a preparation time.
TEST_P(BackendContract, VariantsRenderOcclusionAtTheBoxAndNoneOnOpenFloor) {
  const render::Extent size{160, 90};
  const scene::View view = box_view();
  auto backend = make();
  backend->set_scene(box_on_floor());
  for (const auto& key : backend_test_keys()) {
    SCOPED_TRACE(key);
    const auto p = plan(key);
    auto pipeline = backend->prepare(p, size);
    EXPECT_GT(pipeline->create_ms, 0.0);
    for (int f = 0; f < 3; ++f) {
      const auto times = backend->render(*pipeline, box_frame(view, f));
      ASSERT_EQ(times.size(), p.draws.size());
      for (std::size_t d = 0; d < times.size(); ++d) EXPECT_GT(times[d], 0.0) << p.draws[d].name;
    }
    const auto img = backend->read_result(*pipeline);
    expect_sane(img, size, key);
    expect_box_occlusion(img, size, key);
    EXPECT_EQ(img.at(size.width / 2, size.height - 1), 1.0f) << "background (depth cleared to far) stays open";
  }
}

TEST_P(BackendContract, ProgressiveFramesAlternateAndSettle) {
  const render::Extent size{160, 90};
  const scene::View view = box_view();
  auto backend = make();
  backend->set_scene(box_on_floor());
  auto pipeline = backend->prepare(plan(kContractProgressive), size);
  std::vector<image::FloatImage> frames;
  for (int f = 0; f < 6; ++f) {
    backend->render(*pipeline, box_frame(view, f));
    frames.push_back(backend->read_result(*pipeline));
    expect_sane(frames.back(), size, "frame " + std::to_string(f));
  }
  // Frame 0 averages its half with the open (1.0) history: every average is at least a half, and lighter
  // than from frame 1 on, when both halves are real.
  float lo0 = 1.0f, lo1 = 1.0f;
  for (float v : frames[0].pixels) lo0 = std::min(lo0, v);
  for (float v : frames[1].pixels) lo1 = std::min(lo1, v);
  EXPECT_GE(lo0, 0.5f - 1e-6f);
  EXPECT_LT(lo1, lo0) << "both real halves are darker than one half plus an open history";
  EXPECT_GT(compare(frames[0], frames[1]).mean_abs, 1e-3) << "frame 0 history starts open";
  // Static camera: frame f + 1 averages the same two halves as frame f in the other roles (a + b = b + a
  // exactly); same-parity frames are identical too.
  EXPECT_EQ(compare(frames[4], frames[5]).max_abs, 0.0);
  EXPECT_EQ(compare(frames[3], frames[5]).max_abs, 0.0);
  EXPECT_EQ(compare(frames[2], frames[4]).max_abs, 0.0);
  expect_box_occlusion(frames[5], size, kContractProgressive);

  // The raw AO pass: parity 0 and 1 evaluate different halves of the kernel.
  auto half = backend->prepare(render::plan_prefix(plan(kContractProgressive), "ao"), size);
  backend->render(*half, box_frame(view, 0));
  const auto even = backend->read_result(*half);
  backend->render(*half, box_frame(view, 1));
  const auto odd = backend->read_result(*half);
  EXPECT_GT(compare(even, odd).mean_abs, 1e-3);
}

// The G-buffer's linear depth: cleared to the view's far plane (again when it changes), and row 0 of the
// read-back is the bottom of the view (the floor in front of the camera is nearer than the rows above it).
TEST_P(BackendContract, DepthClearFollowsFarPlaneAndRowZeroIsTheBottom) {
  const render::Extent size{160, 90};
  auto backend = make();
  // The floor alone, looked at from above: the top rows look past its far edge into the background.
  const scene::View near_view = box_view(40.0f), far_view = box_view(80.0f);
  backend->set_scene(quad_scene({square_floor(20)}, near_view, kBoxRadius));
  auto pipeline = backend->prepare(render::plan_prefix(plan(kContractBaseline), "gbuffer"), size);
  for (const auto* view : {&near_view, &far_view, &near_view}) {
    backend->render(*pipeline, box_frame(*view, 0));
    const auto depth = backend->read_result(*pipeline);
    EXPECT_FLOAT_EQ(depth.at(size.width / 2, size.height - 1), view->far_plane) << "background = far";
    const float bottom = depth.at(size.width / 2, 0), middle = depth.at(size.width / 2, size.height / 2);
    EXPECT_GT(bottom, view->near_plane);
    EXPECT_LT(bottom, middle) << "row 0 must be the bottom of the view (nearest floor)";
  }
}

TEST_P(BackendContract, SetSceneReplacesTheGeometryOfPreparedPipelines) {
  const render::Extent size{160, 90};
  const scene::View view = box_view();
  auto backend = make();
  backend->set_scene(box_on_floor());
  auto pipeline = backend->prepare(plan(kContractBaseline), size);
  backend->render(*pipeline, box_frame(view, 0));
  expect_box_occlusion(backend->read_result(*pipeline), size, "box");
  backend->set_scene(quad_scene({square_floor(20)}, view, kBoxRadius));
  backend->render(*pipeline, box_frame(view, 1));
  const auto floor_only = backend->read_result(*pipeline);
  float lo = 1;
  for (float v : floor_only.pixels) lo = std::min(lo, v);
  EXPECT_GE(lo, 0.95f) << "the box must be gone";
}

// set_params replaces a draw's parameter block from the next frame on, as preparing the plan with those
// values would; a draw that does not exist or a block of another size is refused.
TEST_P(BackendContract, SetParamsActsLikePreparingWithTheValues) {
  const render::Extent size{96, 54};
  const scene::View view = box_view();
  const auto& c = kContractVariants.space();
  const int v = variant_index(c, kContractBaseline);
  const auto target = render::target_of(GetParam());
  const auto plain = render::plan_pipeline(c, v, target), dark = render::plan_pipeline(c, v, target, {{"ao.intensity", 3.0}});
  std::size_t ao = 0;
  while (ao < plain.draws.size() && plain.draws[ao].name != "ao") ++ao;
  ASSERT_LT(ao, plain.draws.size());
  ASSERT_NE(plain.draws[ao].params, dark.draws[ao].params) << "the premise: ao.intensity is in the AO block";
  auto backend = make();
  backend->set_scene(box_on_floor());
  const auto expected = render_plan(*backend, dark, view, size, kBoxRadius, 1);
  auto pipeline = backend->prepare(plain, size);
  backend->render(*pipeline, box_frame(view, 0));
  const auto before = backend->read_result(*pipeline);
  backend->set_params(*pipeline, ao, dark.draws[ao].params);
  backend->render(*pipeline, box_frame(view, 0));
  EXPECT_EQ(backend->read_result(*pipeline).pixels, expected.pixels);
  EXPECT_NE(before.pixels, expected.pixels);
  EXPECT_THROW(backend->set_params(*pipeline, plain.draws.size(), dark.draws[ao].params), render::BackendError);
  std::vector<float> longer = dark.draws[ao].params;
  longer.push_back(1.0f);
  EXPECT_THROW(backend->set_params(*pipeline, ao, longer), render::BackendError);
}

TEST_P(BackendContract, PipelinesMayOutliveTheirBackend) {
  std::unique_ptr<render::PreparedPipeline> pipeline;
  const scene::View view = box_view();
  {
    auto backend = make();
    backend->set_scene(box_on_floor());
    pipeline = backend->prepare(plan(kContractProgressive), {64, 36});
    backend->render(*pipeline, box_frame(view, 0));
  }
  pipeline.reset();  // releases its objects, then what it kept of the backend
  auto again = make();  // and the driver still serves a new backend
  again->set_scene(box_on_floor());
  auto p = again->prepare(plan(kContractBaseline), {64, 36});
  EXPECT_NO_THROW(again->render(*p, box_frame(view, 0)));
}

TEST_P(BackendContract, MisuseThrowsBackendError) {
  auto backend = make();
  auto other = make();
  const auto p = plan(kContractBaseline);
  const scene::View view = box_view();
  auto pipeline = backend->prepare(p, {32, 18});
  EXPECT_THROW(backend->read_result(*pipeline), render::BackendError) << "nothing rendered yet";
  EXPECT_THROW(backend->render(*pipeline, box_frame(view, 0)), render::BackendError) << "no scene";
  backend->set_scene(box_on_floor());
  other->set_scene(box_on_floor());
  EXPECT_THROW(other->render(*pipeline, box_frame(view, 0)), render::BackendError) << "another backend's";
  EXPECT_THROW(backend->prepare(p, {0, 18}), render::BackendError);
  scene::Scene broken = box_on_floor();
  broken.indices.push_back(99999);
  broken.indices.push_back(0);
  broken.indices.push_back(1);
  EXPECT_THROW(backend->set_scene(broken), render::BackendError);
}

// A program the driver rejects (SPIR-V that is not SPIR-V, GLSL that does not compile) names its program key
// in one line, and the backend prepares and renders the real plan afterwards.
TEST_P(BackendContract, RejectedShaderNamesItsProgramAndLeavesTheBackendUsable) {
  auto backend = make();
  backend->set_scene(box_on_floor());
  const auto p = plan(kContractBaseline);
  const int fragment = p.draws[1].fragment;
  auto broken = p;
  if (GetParam() == "lavapipe") broken.shaders[fragment].spirv[0] = 0x12345678;
  else broken.shaders[fragment].glsl += "\nvoid broken_here() { undefined_thing = 1; }\n";
  const std::string what = thrown_message([&] { backend->prepare(broken, {32, 18}); });
  EXPECT_TRUE(has_text(what, p.shaders[fragment].program_key)) << what;
  EXPECT_TRUE(is_one_line(what)) << what;
  EXPECT_THROW(backend->prepare(broken, {32, 18}), render::BackendError);
  auto pipeline = backend->prepare(p, {32, 18});
  EXPECT_NO_THROW(backend->render(*pipeline, box_frame(box_view(), 0)));
}

// Every built-in backend: a backend added to the registry is held to the contract with no edit here.
std::vector<std::string> contract_backends() {
  std::vector<std::string> names;
  for (const auto& b : render::builtin_backends()) names.push_back(b.name);
  return names;
}

// Those that run a GL target (GLSL source).
std::vector<std::string> contract_gl_backends() {
  std::vector<std::string> names;
  for (const auto& b : render::builtin_backends())
    if (b.target != variants::Target::vulkan) names.push_back(b.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Backends, BackendContract, ::testing::ValuesIn(contract_backends()),
                         [](const auto& info) { return info.param; });

// The GL backends on hand-written programs: a fullscreen triangle and a fragment shader that writes known
// numbers, in each backend's GLSL (desktop 4.50 core, ES 3.00 with highp: ES defaults int to mediump, and
// llvmpipe runs float(mediump int) in fp16, which turned 3001 into 3000).
class GlBackendContract : public ::testing::TestWithParam<std::string> {
 protected:
  std::string header() const {
    return GetParam() == "gles" ? "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                                : "#version 450 core\n";
  }
  render::PipelinePlan fullscreen_plan(const std::string& fragment_key, const std::string& fragment_body) const {
    render::PipelinePlan plan;
    plan.variant = "test-" + fragment_key;
    plan.shaders = {glsl_shader("fullscreen.vert", variants::StageKind::vertex,
                           header() + "void main() { gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, "
                                      "gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0); }\n"),
                    glsl_shader(fragment_key, variants::StageKind::fragment,
                           header() + "layout(location = 0) out vec4 o_color;\n" + fragment_body)};
    plan.textures = {render::Texture{"result", render::Format::r32f}};
    render::Draw d;
    d.name = d.pass = "pattern";
    d.vertex = 0;
    d.fragment = 1;
    d.outputs = {render::TextureRef{0}};
    plan.draws = {d};
    plan.result = 0;
    return plan;
  }
};

// Read-back (glGetTexImage on osmesa, glReadPixels from an FBO on ES): row order, exact values, NaN and Inf,
// at an odd width (rows are not a multiple of 8 bytes).
TEST_P(GlBackendContract, ReadBackKeepsRowOrderExactValuesNaNAndInf) {
  auto backend = render::make_backend(GetParam(), {});
  auto p = backend->prepare(fullscreen_plan("pattern.frag", kReadbackPatternMain), {37, 5});
  EXPECT_THROW(backend->read_result(*p), render::BackendError) << "nothing rendered yet";
  scene::View view;
  render::FrameSetup f;
  f.view = &view;
  backend->render(*p, f);
  expect_readback_pattern(backend->read_result(*p), 37, 5);
}

// The driver's compile log reaches the error with the program key, in one line, and the backend stays usable.
TEST_P(GlBackendContract, ShaderThatFailsToCompileNamesItsProgramKeyAndTheDriversLog) {
  auto backend = render::make_backend(GetParam(), {});
  const std::string what = thrown_message([&] {
    backend->prepare(fullscreen_plan("broken-key.frag", "void main() { o_color = undefined_thing; }\n"), {8, 8});
  });
  EXPECT_TRUE(has_text(what, "broken-key.frag")) << what;
  EXPECT_TRUE(has_text(what, "undefined_thing")) << what;
  EXPECT_TRUE(is_one_line(what)) << what;
  auto p = backend->prepare(fullscreen_plan("half.frag", "void main() { o_color = vec4(0.5); }\n"), {8, 8});
  scene::View view;
  render::FrameSetup f;
  f.view = &view;
  backend->render(*p, f);
  EXPECT_EQ(backend->read_result(*p).at(3, 3), 0.5f);
}

INSTANTIATE_TEST_SUITE_P(GlBackends, GlBackendContract, ::testing::ValuesIn(contract_gl_backends()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace aovar::test
