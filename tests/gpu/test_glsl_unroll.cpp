// Loops unrolled in GLSL source for the GL compilers' statistics (src/gpu/gl/unroll.h): constant bounds
// (literals and `const int`s) unroll into copies that glslang still accepts, `continue` and a loop's own
// `break` keep their meaning, run-time bounds stay loops, and the templates' real programs lose every loop
// whose trip count is known.
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
  EXPECT_FALSE(gpu::eval_int("min(4, 2)", v));
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
