// Loops unrolled in GLSL source for the GL compilers' statistics (src/gpu/gl/unroll.h): constant bounds
// (literals and `const int`s) unroll into copies that glslang still accepts, `continue` and a loop's own
// `break` keep their meaning, run-time bounds stay loops, and the templates' real programs lose every loop
// whose trip count is known; a blur's radius-bounded loops unroll at the radius the variant renders with.
#include <gtest/gtest.h>

#include <regex>

#include "compile/glslang_compiler.h"
#include "gpu/gl/unroll.h"
#include "render_support.h"

namespace aovar {
namespace {

int count_of(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

int loops_in(const std::string& s) {  // glslang's preprocessor writes "for(" or "for ("
  const std::regex loop(R"(\bfor\s*\()");
  return static_cast<int>(std::distance(std::sregex_iterator(s.begin(), s.end(), loop), std::sregex_iterator()));
}

bool valid_unrolled_es(const std::string& source) {
  return compile::compile_program(source, variants::StageKind::fragment, variants::Target::gles30).ok;
}

const char* kUnrollHead = "#version 300 es\nprecision highp float;\nout vec4 o;\nuniform float u[8];\n";

TEST(GlslUnroll, EvaluatesIntegerConstantExpressions) {
  long v = 0;
  EXPECT_TRUE(gpu::eval_int("(32 / 2) - 1", v));
  EXPECT_EQ(v, 15);
  EXPECT_TRUE(gpu::eval_int("-3 * (2 + 1) % 4", v));
  EXPECT_EQ(v, -1);
  EXPECT_TRUE(gpu::eval_int("TAPS / 2", v, {{"TAPS", 12}}));
  EXPECT_EQ(v, 6);
  EXPECT_FALSE(gpu::eval_int("bound", v));
  EXPECT_FALSE(gpu::eval_int("hypot(4, 2)", v));
  EXPECT_FALSE(gpu::eval_int("4 / 0", v));
  // The templates' sample ladders: AO_SLICE_STEPS and HBAO_STEPS (common/slices.glsl, ao/hbao.glsl).
  const char* steps = "S < 4 ? 1 : (S > 16 ? 4 : S / 4)";
  for (const auto& [samples, expected] : {std::pair{2L, 1L}, {8L, 2L}, {16L, 4L}, {32L, 4L}}) {
    EXPECT_TRUE(gpu::eval_int(steps, v, {{"S", samples}}));
    EXPECT_EQ(v, expected) << samples;
  }
  EXPECT_TRUE(gpu::eval_int("1 == 1 && 2 != 3 || 0", v));
  EXPECT_EQ(v, 1);
  EXPECT_TRUE(gpu::eval_int("3 >= 3 ? 5 <= 4 : 7", v));
  EXPECT_EQ(v, 0);
  // What no bound can be fails instead of overflowing or throwing: the loop then stays rolled.
  EXPECT_FALSE(gpu::eval_int("9223372036854775807 + 1", v));
  EXPECT_FALSE(gpu::eval_int("4611686018427387904 * 2", v));
  EXPECT_FALSE(gpu::eval_int("-(-9223372036854775807 - 1)", v));
  EXPECT_FALSE(gpu::eval_int("(-9223372036854775807 - 1) / -1", v));
  EXPECT_FALSE(gpu::eval_int("99999999999999999999", v));
  EXPECT_FALSE(gpu::eval_int("int(1e999)", v));
  EXPECT_FALSE(gpu::eval_int("int(1e308 * 10.0 - 1e308 * 10.0)", v)) << "NaN";
}

// The forms a blur's bound is computed in (passes/blur_separable.frag): float literals and inputs, int()'s
// truncation, clamp / min / max, and textureSize's components standing for a large extent.
TEST(GlslUnroll, EvaluatesTheFormsOfARunTimeBound) {
  long v = 0;
  const auto is = [&](const std::string& expr, long expected, const gpu::GlslInputs& inputs = {}) {
    v = -99;
    EXPECT_TRUE(gpu::eval_int(expr, v, {{"MAXR", 8}}, inputs)) << expr;
    EXPECT_EQ(v, expected) << expr;
  };
  is("int(3.7)", 3);
  is("int(-2.5)", -2);  // toward zero, as GLSL's int()
  is("int(.5) + int(2.5e0) + int(1.5f) + int(3.)", 0 + 2 + 1 + 3);
  is("int(float(7) / 2.0)", 3);
  is("min(max(1, 2), 3)", 2);
  is("abs(-4)", 4);
  const std::string r = "clamp(int(params.radius_px), 1, MAXR)";
  is(r, 3, {{"params.radius_px", 3.0}});
  is(r, 1, {{"params.radius_px", 0.5}});
  is(r, 8, {{"params.radius_px", 12.0}});
  is("min(" + r + ", max(textureSize(t, 0).x, textureSize(t, 0).y))", 2, {{"params.radius_px", 2.9}});
  is("max(textureSize(ao_input_tex, 0).y, 2)", gpu::kTextureExtent);
  EXPECT_FALSE(gpu::eval_int("3.0", v)) << "a float is no loop bound";
  EXPECT_FALSE(gpu::eval_int("1.0 % 2.0", v));
  EXPECT_FALSE(gpu::eval_int("int(params.radius_px)", v)) << "no value given";
  EXPECT_FALSE(gpu::eval_int("textureSize(t, 0)", v)) << "a vector";
  EXPECT_FALSE(gpu::eval_int("min(1)", v));
  EXPECT_FALSE(gpu::eval_int("3x", v));
}

TEST(GlslUnroll, ConstantLoopsBecomeCopiesGlslangAccepts) {
  const std::string src = std::string(kUnrollHead) +
                          "const int N = 8;\nconst int HALF = N / 2;\n"
                          "void main() { float s = 0.0;\n"
                          "  for (int k = 0; k < HALF; ++k) { if (u[k] < 0.0) { continue; } s += u[k]; }\n"
                          "  for (int j = 3; j >= 0; --j) { s *= 0.5; }\n  o = vec4(s); }\n";
  ASSERT_TRUE(valid_unrolled_es(src));
  const auto r = gpu::unroll_loops(compile::preprocess_es(src, variants::StageKind::fragment));
  EXPECT_EQ(r.unrolled, 2);
  EXPECT_EQ(r.kept, 0);
  EXPECT_EQ(loops_in(r.source), 0);
  EXPECT_EQ(count_of(r.source, "const int k = "), 4);  // HALF = 4 copies
  EXPECT_EQ(count_of(r.source, "const int j = "), 4);
  EXPECT_NE(r.source.find("const int j = 3;"), std::string::npos);
  EXPECT_NE(r.source.find("const int j = 0;"), std::string::npos);
  EXPECT_TRUE(valid_unrolled_es(r.source)) << r.source;
}

TEST(GlslUnroll, ALoopsOwnBreakSkipsTheLaterCopiesAndANestedLoopsBreakStaysItsOwn) {
  const std::string src = std::string(kUnrollHead) +
                          "void main() { float s = 0.0;\n"
                          "  for (int i = 0; i < 3; ++i) {\n"
                          "    for (int j = 0; j < 2; ++j) { if (u[j] > 1.0) break; s += 1.0; }\n"
                          "    if (s > 4.0) { break; }\n  }\n  o = vec4(s); }\n";
  const auto r = gpu::unroll_loops(compile::preprocess_es(src, variants::StageKind::fragment));
  EXPECT_EQ(r.unrolled, 1 + 3);  // the outer loop, and the inner one in each of its 3 copies
  // Every break now also sets its loop's flag: the outer loop's in its 3 copies, the inner loop's in its 2 copies
  // within each of them.
  EXPECT_EQ(count_of(r.source, "= true; break; }"), 3 + 3 * 2);
  EXPECT_EQ(count_of(r.source, "if (!aovar_break_0)"), 2);  // the outer loop's later copies are skipped after it
  EXPECT_TRUE(valid_unrolled_es(r.source)) << r.source;
}

TEST(GlslUnroll, RunTimeBoundsStayLoops) {
  const std::string src = std::string(kUnrollHead) +
                          "uniform int r;\nvoid main() { float s = 0.0;\n"
                          "  for (int i = -r; i <= r; ++i) { for (int k = 0; k < 2; ++k) { s += u[k]; } }\n"
                          "  o = vec4(s); }\n";
  const auto r = gpu::unroll_loops(compile::preprocess_es(src, variants::StageKind::fragment));
  EXPECT_EQ(r.kept, 1);
  EXPECT_EQ(r.unrolled, 1);  // the constant inner loop inside the kept one
  EXPECT_EQ(loops_in(r.source), 1);
  EXPECT_TRUE(valid_unrolled_es(r.source)) << r.source;
}

// A bound computed from an input through locals unrolls; one from a local written again, or from no value,
// stays a loop.
TEST(GlslUnroll, ABoundComputedFromAnInputUnrollsAtItsValue) {
  const std::string src = std::string(kUnrollHead) +
                          "uniform P { float radius; float other; } params;\nuniform sampler2D t;\n"
                          "void main() { float s = 0.0;\n"
                          "  int r = clamp(int(params.radius), 1, 8);\n"
                          "  ivec2 size = textureSize(t, 0);\n"
                          "  int bound = min(r, max(size.x, size.y));\n"
                          "  for (int i = -bound; i <= bound; ++i) { s += u[i + 3] * float(r); }\n"
                          "  int n = 2;\n  n += 1;\n"
                          "  for (int k = 0; k < n; ++k) { s += 1.0; }\n  o = vec4(s); }\n";
  ASSERT_TRUE(valid_unrolled_es(src));
  const std::string pre = compile::preprocess_es(src, variants::StageKind::fragment);
  const auto at3 = gpu::unroll_loops(pre, {{"params.radius", 3.0}, {"params.other", 0.5}});
  EXPECT_EQ(at3.unrolled, 1);
  EXPECT_EQ(at3.kept, 1);  // `n` is written twice
  EXPECT_EQ(count_of(at3.source, "const int i = "), 7);
  EXPECT_EQ(at3.specialised, (gpu::GlslInputs{{"params.radius", 3.0}})) << "only what a bound read";
  EXPECT_NE(at3.source.find("float(r)"), std::string::npos) << "the input's other reads stay";
  EXPECT_TRUE(valid_unrolled_es(at3.source)) << at3.source;
  const auto none = gpu::unroll_loops(pre);
  EXPECT_EQ(none.kept, 2);
  EXPECT_TRUE(none.specialised.empty());
}

// Names are not scoped: a local `int n = 4` of one function must not give another function's parameter `n` a
// value, so that function's loop over `n` stays a loop.
TEST(GlslUnroll, AParametersNameIsNeverTakenFromALocalElsewhere) {
  const std::string src = std::string(kUnrollHead) +
                          "float f(int n) { float s = 0.0; for (int i = 0; i < n; ++i) { s += u[i]; } return s; }\n"
                          "void main() { int n = 4; float s = 0.0;\n"
                          "  for (int k = 0; k < n; ++k) { s += u[k]; }\n  o = vec4(s + f(2)); }\n";
  ASSERT_TRUE(valid_unrolled_es(src));
  const auto r = gpu::unroll_loops(compile::preprocess_es(src, variants::StageKind::fragment));
  EXPECT_EQ(r.unrolled, 0);
  EXPECT_EQ(r.kept, 2);
  EXPECT_TRUE(valid_unrolled_es(r.source)) << r.source;
}

// The real blurs (passes/blur_separable.frag, passes/blur_bilateral.frag) at the radius their parameter gives:
// 2R + 1 copies of the tap, (2R + 1)^2 for the 2-D bilateral, no loop left, glslang still accepting them.
TEST(GlslUnroll, TheBlursUnrollToTheirTapsAtTheRadius) {
  const auto c = test::compile_variants({"alchemy-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp",
                                         "alchemy-s08-p0-nrgb8-zdep-rst-d16-bbil-x1-hp"},
                                        true);
  int blurs = 0;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto plan = render::plan_pipeline(c, static_cast<int>(v), variants::Target::gles30);
    for (const auto& draw : plan.draws) {
      if (draw.pass != "blur") continue;
      const auto& shader = plan.shaders[draw.fragment];
      const std::string pre = compile::preprocess_es(shader.glsl, shader.stage);
      const bool bilateral = shader.program_key.find("bilateral") != std::string::npos;
      EXPECT_EQ(gpu::unroll_loops(pre).kept, bilateral ? 2 : 1) << "no radius: " << shader.program_key;
      for (int radius : {1, 3, 8}) {
        const auto r = gpu::unroll_loops(pre, {{"params.radius_px", radius + 0.5}, {"params.depth_sigma", 0.05}});
        const int taps = 2 * radius + 1;
        EXPECT_EQ(r.kept, 0) << shader.program_key;
        EXPECT_EQ(loops_in(r.source), 0) << shader.program_key;
        EXPECT_EQ(r.specialised, (gpu::GlslInputs{{"params.radius_px", radius + 0.5}}));
        if (bilateral) {
          EXPECT_EQ(count_of(r.source, "const int y = "), taps);
          EXPECT_EQ(count_of(r.source, "const int x = "), taps * taps);
        } else {
          EXPECT_EQ(count_of(r.source, "const int i = "), taps);
        }
        if (radius == 3) {
          EXPECT_TRUE(valid_unrolled_es(r.source)) << shader.program_key;
        }
      }
      ++blurs;
      break;  // the separable blur's second draw is the same program
    }
  }
  EXPECT_EQ(blurs, 2);
}

TEST(GlslUnroll, TheTemplatesAoPassesLoseEveryConstantLoop) {
  // One program per method family of loops: taps (alchemy), pairs (vo), directions x steps (hbao), slices x
  // steps (gtao, vbao), and the z-pyramid's level loop.
  const auto c = test::compile_variants({"alchemy-s32-p0-ndep-zdep-rst-d16-bsep-x1-hp-zmip",
                                         "vo-s16-p0-ndep-zdep-_r-d16-bsep-x1-hp", "hbao-s16-p0-nrgb8-zdep-rst-d16-bsep-x1-hp",
                                         "gtao-s16-p0-nrgb8-zdep-rst-d16-bsep-x1-hp", "vbao-s16-p0-nrgb8-zdep-rst-d16-bsep-x1-hp"},
                                        true);
  int programs = 0;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto plan = render::plan_pipeline(c, static_cast<int>(v), variants::Target::gles30);
    for (const auto& shader : plan.shaders) {
      if (shader.program_key.rfind(c.space.variants[v].key.substr(0, 3), 0) != 0) continue;  // the AO programs
      const auto r = gpu::unroll_loops(compile::preprocess_es(shader.glsl, shader.stage));
      EXPECT_GT(r.unrolled, 0) << shader.program_key;
      EXPECT_EQ(r.kept, 0) << shader.program_key;
      EXPECT_TRUE(valid_unrolled_es(r.source)) << shader.program_key;
      ++programs;
    }
  }
  EXPECT_GE(programs, 5);
}

}  // namespace
}  // namespace aovar
