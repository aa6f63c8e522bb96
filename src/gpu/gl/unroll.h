#pragma once
// Loops unrolled in GLSL source, for the GL compilers' statistics only (never shipped). Mesa's GL drivers keep
// a loop of many iterations rolled (nouveau's GT200 and Midgard report a loop at s32; nvc0 and freedreno report
// fewer instructions at s32 than at s16), so the sample count would not show in their statistics. The Vulkan
// path marks loops Unroll in SPIR-V (gpu/spirv_unroll.h), but GLSL has no such hint and SPIRV-Tools' unroller
// refuses the templates' loops (a `continue` makes a second back edge), so the unroll happens here, on the
// preprocessed source (compile::preprocess_es), where the bounds are integer constants or `const int`s.
//
// A loop `for (int i = A; i < B; ++i) { body }` (also <=, > and >= with ++/--, A and B integer constant
// expressions) becomes, per value v of i, `{ const int i = v; do { body } while (false); }`: `continue` then
// ends the iteration as before, and a `break` of that loop sets a flag that skips the later copies. Loops with
// run-time bounds (the blurs' radius, clamped to the image) stay loops and are counted.
#include <map>
#include <string>

namespace aovar::gpu {

struct GlslUnroll {
  std::string source;  // the preprocessed source with every loop of constant bounds unrolled
  int unrolled = 0;    // loops unrolled (each copy of an inner loop counts)
  int kept = 0;        // loops left rolled: run-time bounds, or more than kMaxCopies iterations
};

constexpr int kMaxCopies = 256;  // iterations one loop may expand into

// `preprocessed` is compile::preprocess_es's output. Throws std::runtime_error for unbalanced braces.
GlslUnroll unroll_loops(const std::string& preprocessed);

// An integer constant expression of literals, `names` (the source's `const int` constants), + - * / %, unary
// minus, parentheses, comparisons, && || and ?: ("AO_SAMPLES < 4 ? 1 : AO_SAMPLES / 4"): true and its value, or false when it holds anything else (an
// unknown name, a call).
bool eval_int(const std::string& expr, long& value, const std::map<std::string, long>& names = {});

// The source's `const int NAME = EXPR;` declarations whose EXPR evaluates (in order: later ones may use earlier).
std::map<std::string, long> int_constants(const std::string& source);

}  // namespace aovar::gpu
