// mediump as fp16 on lavapipe (BackendOptions::mediump_as_fp16, compile/relaxed_fp16.h): the rewrite emits real
// half-precision arithmetic, llvmpipe executes it as fp16 (overflow to Inf, 11-bit rounding), a mediump AO variant
// then differs from its highp partner (it does not without the flag), and highp programs are left alone.
#include <gtest/gtest.h>

#include "image/health.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include "compile/glslang_compiler.h"
#include "compile/relaxed_fp16.h"
#include "measure/measure.h"
#include "render/gl/gl_backends.h"
#include "render/vulkan/lavapipe.h"
#include "render_support.h"

namespace aovar::test {
namespace {

using Words = std::vector<std::uint32_t>;

// Squares a uniform (never a constant: nothing may fold it) at the precision `precision`.
std::string probe_fragment(const char* precision) {
  return std::string(R"(#version 450
layout(std140, set = 0, binding = 1) uniform AOParams { float x; } params;
layout(location = 0) out vec4 o_color;
void main() {
  )") + precision + " float v = params.x;\n  " + precision + R"( float square = v * v;
  o_color = vec4(square, 0.0, 0.0, 1.0);
}
)";
}

const char* kFullscreenVertex = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

Words compile_glsl(const std::string& source, variants::StageKind stage) {
  auto out = compile::compile_program(source, stage, variants::Target::vulkan);
  if (!out.ok) throw std::runtime_error("probe shader failed to compile");
  return out.spirv;
}

// Instructions with opcode `op` whose result type is `type` (opcodes with type, result, ...).
int count_typed(const Words& w, std::uint32_t op, std::uint32_t type) {
  int n = 0;
  for (std::size_t i = 5; i < w.size() && (w[i] >> 16); i += w[i] >> 16)
    n += (w[i] & 0xffff) == op && (w[i] >> 16) >= 3 && w[i + 1] == type;
  return n;
}

// Id of `OpTypeFloat 16`, 0 when absent.
std::uint32_t half_type(const Words& w) {
  constexpr std::uint32_t kOpTypeFloat = 22;
  for (std::size_t i = 5; i < w.size() && (w[i] >> 16); i += w[i] >> 16)
    if ((w[i] & 0xffff) == kOpTypeFloat && w[i + 2] == 16) return w[i + 1];
  return 0;
}

constexpr std::uint32_t kOpFMul = 133;

TEST(MediumpFp16, RewritesRelaxedArithmeticToHalf) {
  Words mediump = compile_glsl(probe_fragment("mediump"), variants::StageKind::fragment);
  ASSERT_TRUE(compile::has_relaxed_precision(mediump));
  ASSERT_EQ(half_type(mediump), 0u);
  auto start = std::chrono::steady_clock::now();
  Words fp16 = compile::relaxed_precision_to_fp16(mediump);
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::uint32_t half = half_type(fp16);
  ASSERT_NE(half, 0u) << "no OpTypeFloat 16 after the rewrite";
  EXPECT_EQ(count_typed(fp16, kOpFMul, half), 1) << "the mediump square is not an fp16 OpFMul";
  std::cout << "probe: " << mediump.size() << " -> " << fp16.size() << " words in " << ms << " ms\n";
}

TEST(MediumpFp16, HighpModulesComeBackAsIsAndBadInputThrows) {
  Words highp = compile_glsl(probe_fragment("highp"), variants::StageKind::fragment);
  EXPECT_FALSE(compile::has_relaxed_precision(highp));
  EXPECT_EQ(compile::relaxed_precision_to_fp16(highp), highp);

  EXPECT_THROW(compile::relaxed_precision_to_fp16({0x12345678, 0, 0, 0, 0}), std::runtime_error);
  Words broken = compile_glsl(probe_fragment("mediump"), variants::StageKind::fragment);
  broken.resize(broken.size() - 2);  // cuts the last instruction (OpFunctionEnd): invalid, decorations intact
  ASSERT_TRUE(compile::has_relaxed_precision(broken));
  const std::string m = thrown_message<std::runtime_error>([&] { compile::relaxed_precision_to_fp16(broken); });
  EXPECT_NE(m.find("mediump->fp16"), std::string::npos) << m;
}

// One fullscreen draw of the probe into the r32f result, with AOParams.x = x.
render::PipelinePlan probe_plan() {
  render::PipelinePlan plan;
  plan.variant = "probe";
  for (auto stage : {variants::StageKind::vertex, variants::StageKind::fragment}) {
    render::Shader sh;
    sh.stage = stage;
    bool vertex = stage == variants::StageKind::vertex;
    sh.program_key = vertex ? "probe.vert" : "probe.frag";
    sh.spirv = compile_glsl(vertex ? kFullscreenVertex : probe_fragment("mediump"), stage);
    plan.shaders.push_back(sh);
  }
  render::Texture result;
  result.name = "result";
  result.format = render::Format::r32f;
  plan.textures = {result};
  render::Draw d;
  d.name = d.pass = "probe";
  d.vertex = 0;
  d.fragment = 1;
  d.params = {0.0f};
  d.outputs = {{0}};
  plan.draws = {d};
  plan.result = 0;
  return plan;
}

float render_square(render::Backend& backend, render::PreparedPipeline& p, float x) {
  backend.set_params(p, 0, {x});
  scene::View view = floor_view();
  render::FrameSetup s;
  s.view = &view;
  backend.render(p, s);
  return backend.read_result(p).at(1, 1);
}

TEST(MediumpFp16, LavapipeOverflowsAndRoundsLikeFp16OnlyWithTheFlag) {
  const float x_round = 1.0f + 1.0f / 4096.0f;  // a quarter of an fp16 ulp above 1: fp16 rounds it to 1
  for (bool fp16 : {false, true}) {
    render::BackendOptions o;
    o.mediump_as_fp16 = fp16;
    o.validation = true;  // the Float16 capability must match the enabled feature
    auto backend = render::make_lavapipe_backend(o);
    EXPECT_EQ(backend->info().mediump_fp16, fp16);
    auto p = backend->prepare(probe_plan(), {4, 4});
    float big = render_square(*backend, *p, 300.0f), near_one = render_square(*backend, *p, x_round);
    std::cout << "probe fp16=" << fp16 << ": 300^2 = " << big << ", (1+2^-12)^2 = " << near_one << "\n";
    if (fp16) {
      EXPECT_TRUE(std::isinf(big) && big > 0) << big << ": 90000 > 65504 must overflow in fp16";
      EXPECT_EQ(near_one, 1.0f);
    } else {
      EXPECT_EQ(big, 90000.0f);
      EXPECT_EQ(near_one, x_round * x_round);
    }
  }
}

// mediump/highp partners (the mediump key first) on builtin:atrium.
const std::vector<std::pair<std::string, std::string>> kPairs = {
    {"alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-mp", "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp"},
    {"crytek-s08-p0-ndep-zdep-_r-d16-bsep-x1-mp", "crytek-s08-p0-ndep-zdep-_r-d16-bsep-x1-hp"},
    {"gtao-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-mp", "gtao-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp"},
    {"hbao-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-mp", "hbao-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp"},
    {"homebrew-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-mp", "homebrew-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp"},
    {"sao-s08-p0-ndep-zdep-rst-d16-bsep-x1-mp", "sao-s08-p0-ndep-zdep-rst-d16-bsep-x1-hp"},
    {"sc2-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-mp", "sc2-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp"},
    {"unsharp-s08-p0-ndep-zdep-_r-d16-bsep-x1-mp", "unsharp-s08-p0-ndep-zdep-_r-d16-bsep-x1-hp"},
    {"vo-s08-p0-ndep-zdep-_r-d16-bsep-x1-mp", "vo-s08-p0-ndep-zdep-_r-d16-bsep-x1-hp"},
};

const compile::CompiledSpace& pair_space() {
  static const compile::CompiledSpace c = [] {
    std::vector<std::string> keys;
    for (const auto& [mp, hp] : kPairs) keys.insert(keys.end(), {mp, hp});
    return compile_variants(keys);
  }();
  return c;
}

// Every view of builtin:atrium side by side (one image per view, concatenated).
std::vector<image::FloatImage> render_views(bool fp16, const std::string& key) {
  static const scene::Scene sc = scene::load_scene("builtin:atrium");
  render::BackendOptions o;
  o.mediump_as_fp16 = fp16;
  auto backend = render::make_lavapipe_backend(o);
  backend->set_scene(sc);
  auto plan = render::plan_pipeline(pair_space(), variant_index(pair_space(), key), variants::Target::vulkan);
  std::vector<image::FloatImage> out;
  for (const auto& view : sc.views) out.push_back(render_plan(*backend, plan, view, {320, 180}, sc.ao_radius, 2));
  return out;
}

ImageDiff compare_views(const std::vector<image::FloatImage>& a, const std::vector<image::FloatImage>& b) {
  ImageDiff total;
  for (std::size_t v = 0; v < a.size(); ++v) {
    ImageDiff d = compare(a[v], b[v]);
    total.max_abs = std::max(total.max_abs, d.max_abs);
    total.mean_abs += d.mean_abs / static_cast<double>(a.size());
  }
  return total;
}

TEST(MediumpFp16, MediumpVariantsDifferFromHighpOnlyWithTheFlag) {
  for (const auto& [mp, hp] : kPairs) {
    auto highp = render_views(false, hp);
    ImageDiff off = compare_views(render_views(false, mp), highp);
    auto mp16 = render_views(true, mp);
    ImageDiff on = compare_views(mp16, highp);
    std::cout << mp << " vs highp: fp32 mediump max " << off.max_abs << " mean " << off.mean_abs
              << "; fp16 mediump max " << on.max_abs << " mean " << on.mean_abs << "\n";
    EXPECT_LE(off.max_abs, 1e-6) << mp << ": llvmpipe runs mediump in fp32";
    EXPECT_GT(on.max_abs, 0.0) << mp << ": fp16 changed nothing";
    EXPECT_LE(on.mean_abs, 1.0 / 255.0) << mp;
    EXPECT_LE(on.max_abs, 0.1) << mp;
    for (const auto& img : mp16) {
      auto h = image::health(img);
      EXPECT_EQ(h.nan + h.inf + h.out_of_range, 0) << mp << ": " << h.nan << " NaN, " << h.inf << " Inf, "
                                                   << h.out_of_range << " outside [0, 1]";
    }
  }
}

TEST(MediumpFp16, MediumpVariantRendersCleanUnderValidation) {
  render::BackendOptions o;
  o.validation = true;
  o.mediump_as_fp16 = true;
  auto backend = render::make_lavapipe_backend(o);
  auto view = floor_view();
  backend->set_scene(quad_scene({kFloor, kWall}, view, 0.5f));
  const std::string& mp = kPairs.front().first;
  auto plan = render::plan_pipeline(pair_space(), variant_index(pair_space(), mp), variants::Target::vulkan);
  EXPECT_NO_THROW(render_plan(*backend, plan, view, {64, 36}, 0.5f, 2)) << mp;
}

TEST(MediumpFp16, HighpVariantIsUnchangedByTheFlag) {
  const std::string& hp = kPairs.front().second;
  auto with = render_views(true, hp), without = render_views(false, hp);
  for (std::size_t v = 0; v < with.size(); ++v) EXPECT_EQ(with[v].pixels, without[v].pixels) << hp << " view " << v;
}

TEST(MediumpFp16, OsmesaRejectsTheFlag) {
  render::BackendOptions o;
  o.mediump_as_fp16 = true;
  const std::string m = thrown_message<render::BackendError>([&] { render::make_osmesa_backend(o); });
  EXPECT_NE(m.find("lavapipe only"), std::string::npos) << m;
}

}  // namespace
}  // namespace aovar::test
