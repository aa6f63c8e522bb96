// aovar analyze: static counts of small hand-written shaders with known answers, and the AO methods'
// fetch counts against shader_src/README.md's table (and, printed beside them, Sunet 2018, table 5.7).
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <string>

#include "analyze/analyze.h"
#include "compile/generate.h"
#include "test_support.h"
#include "compile/glslang_compiler.h"

using namespace aovar;

namespace {

analyze::ProgramCost cost_of(const std::string& body) {
  std::string src = R"(#version 450
layout(binding = 2) uniform sampler2D depth_tex;
layout(binding = 3) uniform sampler2D normal_tex;
layout(binding = 7) uniform sampler2D prefilter_tex;
layout(std140, binding = 1) uniform P { float x; int n; } params;
layout(location = 0) out vec4 o_color;
)" + body;
  compile::initialise_compiler();
  auto out = compile::compile_program(src, variants::StageKind::fragment, variants::Target::vulkan);
  std::string diags;
  for (const auto& d : out.diagnostics) diags += fmt::format("{}: {}\n", d.line, d.message);
  EXPECT_TRUE(out.ok) << diags << src;
  if (!out.ok) return {};
  return analyze::analyze_spirv(out.spirv);
}

}  // namespace

TEST(Analyze, ConstantLoopMultipliesFetches) {
  auto c = cost_of(R"(
void main() {
  float s = 0.0;
  for (int k = 0; k < 8; ++k) s += texelFetch(depth_tex, ivec2(k, 0), 0).r;
  o_color = vec4(s);
})");
  EXPECT_EQ(c.fetch(analyze::kDepth), 8);
  EXPECT_EQ(c.fetch(analyze::kNormal), 0);
  ASSERT_EQ(c.loops.size(), 1u);
  EXPECT_TRUE(c.loops[0].constant);
  EXPECT_EQ(c.loops[0].trips, 8);
  EXPECT_FALSE(c.has_dynamic_loop());
}

TEST(Analyze, NestedLoopsMultiply) {
  auto c = cost_of(R"(
void main() {
  float s = texture(normal_tex, vec2(0.5)).x;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) s += texelFetch(depth_tex, ivec2(i, j), 0).r;
  o_color = vec4(s);
})");
  EXPECT_EQ(c.fetch(analyze::kDepth), 12);
  EXPECT_EQ(c.fetch(analyze::kNormal), 1);
  ASSERT_EQ(c.loops.size(), 2u);
  int depth_sum = c.loops[0].depth + c.loops[1].depth;
  EXPECT_EQ(depth_sum, 1);  // one outer, one inner
}

TEST(Analyze, SymmetricAndSteppedLoops) {
  // The blur pattern `for (i = -R; i <= R; ++i)` with a constant R, and a stride of 2.
  auto c = cost_of(R"(
void main() {
  float s = 0.0;
  for (int i = -3; i <= 3; ++i) s += texelFetch(prefilter_tex, ivec2(i, 0), 0).r;
  for (int k = 1; k < 10; k += 2) s += texelFetch(depth_tex, ivec2(k, 0), 0).r;
  o_color = vec4(s);
})");
  EXPECT_EQ(c.fetch(analyze::kPrefilter), 7);
  EXPECT_EQ(c.fetch(analyze::kDepth), 5);
}

TEST(Analyze, RuntimeBoundLoopIsDynamicAndCountedOnce) {
  auto c = cost_of(R"(
void main() {
  float s = 0.0;
  int r = int(params.x);
  for (int i = -r; i <= r; ++i) s += texelFetch(depth_tex, ivec2(i, 0), 0).r;
  o_color = vec4(s);
})");
  EXPECT_EQ(c.fetch(analyze::kDepth), 1);
  ASSERT_EQ(c.loops.size(), 1u);
  EXPECT_FALSE(c.loops[0].constant);
  EXPECT_TRUE(c.has_dynamic_loop());
}

TEST(Analyze, FunctionCalledInLoopIsMultiplied) {
  auto c = cost_of(R"(
vec3 ao_view_position_from_depth(vec2 uv, float z) { return vec3(uv * z, z); }
vec3 ao_position(vec2 uv) { return ao_view_position_from_depth(uv, texture(depth_tex, uv).r); }
float tap(ivec2 p) { return texelFetch(depth_tex, p, 0).r + texelFetch(normal_tex, p, 0).r; }
void main() {
  float s = ao_position(vec2(0.5)).z;
  for (int k = 0; k < 6; ++k) { s += tap(ivec2(k, 1)); s += ao_position(vec2(k)).x; }
  o_color = vec4(s);
})");
  EXPECT_EQ(c.fetch(analyze::kDepth), 1 + 6 + 6);
  EXPECT_EQ(c.fetch(analyze::kNormal), 6);
  EXPECT_EQ(c.position_calls, 7);
  EXPECT_EQ(c.unprojections, 7);  // counted inside ao_position, once each
  EXPECT_EQ(c.projections, 0);
}

TEST(Analyze, ProjectionsAreCountedThroughLoops) {
  auto c = cost_of(R"(
vec2 ao_uv_from_view_position(vec3 p) { return p.xy / -p.z; }
void main() {
  float s = 0.0;
  for (int k = 0; k < 5; ++k) s += texture(depth_tex, ao_uv_from_view_position(vec3(k, 1.0, -2.0))).r;
  o_color = vec4(s, ao_uv_from_view_position(vec3(1.0, 2.0, -3.0)), 1.0);
})");
  EXPECT_EQ(c.projections, 6);
  EXPECT_EQ(c.unprojections, 0);
  EXPECT_EQ(c.fetch(analyze::kDepth), 5);
}

TEST(Analyze, DivisionsTranscendentalsFma) {
  auto c = cost_of(R"(
void main() {
  float a = params.x;
  float s = 1.0 / a + sqrt(a) + inversesqrt(a) + exp2(a) + log(a) + pow(a, 2.0) + atan(a, 1.0);
  for (int k = 0; k < 4; ++k) s += fma(a, s, 1.0) / (a + float(k)) + sin(s);
  s += length(vec3(s)) + (a > 0.5 ? 1.0 : 0.0);
  o_color = vec4(s);
})");
  EXPECT_EQ(c.div, 1 + 4);
  EXPECT_EQ(c.transcendental, 6 + 4);  // sqrt inversesqrt exp2 log pow atan2 + 4 sin
  EXPECT_EQ(c.fma, 4);
  EXPECT_EQ(c.normalize_length, 1);
  EXPECT_GE(c.cmp_select, 2);  // the loop condition, the comparison (and a select or a branch)
  EXPECT_GT(c.alu, c.div + c.transcendental + c.fma);
}

TEST(Analyze, BytesPerPixel) {
  std::map<int, double> f{{analyze::kDepth, 9}, {analyze::kNormal, 1}, {analyze::kPosition, 2}};
  EXPECT_EQ(analyze::bytes_per_pixel(f, analyze::binding_bytes("r16f", "rgb8")), 9 * 2 + 4 + 2 * 16);
  EXPECT_EQ(analyze::bytes_per_pixel(f, analyze::binding_bytes("r32f", "rg8")), 9 * 4 + 2 + 2 * 16);
  EXPECT_THROW(analyze::analyze_spirv({1, 2, 3}), std::runtime_error);
}

// The default manifest's AO programs at N = 8 and 16 against shader_src/README.md's fetch column.
TEST(Analyze, AoMethodFetchesMatchDocumentedCounts) {
  compile::CompileOptions o;
  o.scope.targets = {variants::Target::vulkan};
  for (const char* s : {"08", "16"}) {
    o.globs.push_back(fmt::format("*-s{}-p0-nrgb8-zdep-rst-d32-bsep-x1-hp", s));
    o.globs.push_back(fmt::format("[cuv]*-s{}-p0-ndep-zdep-_r-d32-bsep-x1-hp", s));
    o.globs.push_back(fmt::format("sao-s{}-p0-ndep-zdep-rst-d32-bsep-x1-hp", s));
  }
  auto c = compile::compile_space(aovar::test::on_manifest(o, std::filesystem::path(AOVAR_SOURCE_DIR) / "shader_src/aovar.toml"));
  ASSERT_TRUE(c.ok());
  int ao_pass = -1;
  for (std::size_t p = 0; p < c.manifest.passes.size(); ++p)
    if (c.manifest.passes[p].name == "ao") ao_pass = static_cast<int>(p);
  ASSERT_GE(ao_pass, 0);
  // method -> documented (depth or position, normal, prefilter) as functions of N; Sunet 2018, table 5.7 text.
  // Named per method on purpose: each row is that method's fetch count in shader_src/README.md, which a
  // method added to the shipped manifest documents there and here.
  struct Doc { int depth_plus, normal_per_n, normal_plus, prefilter_per_n, prefilter_plus; bool depth_per_n; const char* seed; };
  const std::map<std::string, Doc> doc = {
      {"alchemy", {1, 0, 1, 0, 0, true, "N+1 depth / 1 normal"}},
      {"homebrew", {1, 1, 1, 0, 0, true, "N+1 depth / N+1 normal"}},
      {"sc2", {1, 0, 1, 0, 0, true, "N+1 depth / 1 normal"}},
      {"crytek", {5, 0, 0, 0, 0, true, "N+1 depth / 0 normal"}},
      {"hbao", {1, 0, 1, 0, 0, true, "1+R(2+S) depth / 0 normal"}},
      {"gtao", {1, 0, 1, 0, 0, true, "-"}},
      {"vbao", {1, 0, 1, 0, 0, true, "-"}},
      {"vo", {5, 0, 0, 0, 0, true, "-"}},
      {"unsharp", {1, 0, 0, 0, 1, false, "-"}},
      {"sao", {0, 0, 0, 1, 1, false, "-"}},  // README: N + 1 z-pyramid texels (binding 7), no depth read
  };
  std::string table = fmt::format("{:<10} {:>3} {:>12} {:>12} {:>12} {:>6} {:>7}  {}\n", "method", "N", "depth+pos",
                                  "normal", "prefilter", "unproj", "loops", "Sunet 2018, table 5.7");
  int checked = 0;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto& var = c.space.variants[v];
    int prog = var.passes[ao_pass][1];
    if (prog < 0) continue;
    std::string method = var.key.substr(0, var.key.find('-'));
    int n = std::stoi(var.key.substr(var.key.find("-s") + 2, 2));
    const auto& build = c.builds[0][prog];
    const auto& b = build.same_as >= 0 ? c.builds[0][build.same_as] : build;
    ASSERT_TRUE(b.ok) << var.key;
    auto cost = analyze::analyze_spirv(b.output.spirv);
    double depth = cost.fetch(analyze::kDepth) + cost.fetch(analyze::kPosition);
    auto it = doc.find(method);
    ASSERT_NE(it, doc.end()) << method << ": document its fetches in shader_src/README.md and in this table";
    const Doc& d = it->second;
    int want_depth = (d.depth_per_n ? n : 0) + d.depth_plus;
    int want_normal = d.normal_per_n * n + d.normal_plus;
    int want_prefilter = d.prefilter_per_n * n + d.prefilter_plus;
    std::string loops;
    for (const auto& l : cost.loops) loops += (loops.empty() ? "" : ",") + (l.constant ? std::to_string(l.trips) : "dyn");
    table += fmt::format("{:<10} {:>3} {:>5g} ({:>4}) {:>5g} ({:>4}) {:>5g} ({:>4}) {:>6g} {:>7}  {}\n", method, n, depth,
                         want_depth, cost.fetch(analyze::kNormal), want_normal, cost.fetch(analyze::kPrefilter),
                         want_prefilter, cost.unprojections, loops, d.seed);
    EXPECT_EQ(depth, want_depth) << var.key;
    EXPECT_EQ(cost.fetch(analyze::kNormal), want_normal) << var.key;
    EXPECT_EQ(cost.fetch(analyze::kPrefilter), want_prefilter) << var.key;
    EXPECT_EQ(cost.fetch(-1), 0) << var.key << ": a texture read whose binding was not resolved";
    // StarCraft II projects each view-space sample back to the screen (README: N projections); no other
    // method projects (their taps are screen offsets).
    EXPECT_EQ(cost.projections, method == "sc2" ? n : 0) << var.key;
    EXPECT_FALSE(cost.has_dynamic_loop()) << var.key;
    ++checked;
  }
  std::cout << "measured (documented in shader_src/README.md)\n" << table;
  EXPECT_EQ(checked, 2 * static_cast<int>(c.manifest.axis_values(variants::Axis::algorithm).size()));  // N = 8, 16
}
