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
// ends the iteration as before, and a `break` of that loop sets a flag that skips the later copies.
//
// The blurs' loops run to a bound computed from a parameter (`int r = clamp(int(params.radius_px), 1, 8)`,
// `int bound = min(r, max(size.x, size.y))` with `size = textureSize(...)`). Given the values the variant renders
// with (`inputs`: "params.radius_px" -> 3), those bounds evaluate too: a local `int` written only by its
// declaration is known when its initialiser is, and textureSize's components stand for kTextureExtent (the
// image at the estimate's frame is always wider than the kernel). So the loop unrolls into its real trip count;
// the parameter's other reads stay uniform reads, so the copies cost what the shipped shader's iterations do
// (literals there would fold the gaussian's `float(r)` into constants the shipped shader never sees). Without
// inputs, or where a bound reads anything else, the loop stays a loop and the compiler counts one iteration.
#include <map>
#include <string>

namespace aovar::gpu {

// Values of uniform reads a loop bound may use, by the name the source reads ("params.radius_px" -> 3).
using GlslInputs = std::map<std::string, double>;

struct GlslUnroll {
  std::string source;  // the preprocessed source with every loop of constant bounds unrolled
  int unrolled = 0;    // loops unrolled (each copy of an inner loop counts)
  int kept = 0;        // loops left rolled: run-time bounds, or more than kMaxCopies iterations
  GlslInputs specialised;  // the inputs an unrolled loop's bounds read: the source depends on exactly these
};

// Iterations one loop may expand into; a loop of more stays rolled (kept) and is counted as one iteration.
// The blurs clamp their radius to 8 (AO_BLUR_MAX_RADIUS), so a blur loop is at most 17 copies and the 2-D
// bilateral's nested pair at most 17 x 17 = 289 bodies: under the cap, which bounds one loop, not a nest.
constexpr int kMaxCopies = 256;

// The extent textureSize's components stand for in a loop bound: larger than any kernel.
constexpr long kTextureExtent = 1L << 16;

// `preprocessed` is compile::preprocess_es's output. Throws std::runtime_error for unbalanced braces.
GlslUnroll unroll_loops(const std::string& preprocessed, const GlslInputs& inputs = {});

// An integer expression of int and float literals (3, 2u, 3.0, .5, 1e1, 2.5f), `names` (the source's `const
// int` constants; dotted names too), `inputs` (float values), + - * / %, unary minus, parentheses, comparisons,
// && || and ?: ("AO_SAMPLES < 4 ? 1 : AO_SAMPLES / 4"), and the calls int() (truncating, as GLSL's), float(),
// min(), max(), clamp(), abs() and textureSize(...).x/.y/.z (kTextureExtent). Mixed int and float arithmetic
// is done in float. True and its value when the result is an int, false when the expression holds anything
// else (an unknown name or call, a division by zero) or its result is a float.
bool eval_int(const std::string& expr, long& value, const std::map<std::string, long>& names = {},
              const GlslInputs& inputs = {});

// The source's `const int NAME = EXPR;` declarations whose EXPR evaluates (in order: later ones may use earlier).
std::map<std::string, long> int_constants(const std::string& source);

}  // namespace aovar::gpu
