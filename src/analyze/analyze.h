#pragma once
// Static cost of SPIR-V fragment programs (issue 6 point 1): texture reads per sampler binding, ALU,
// FMA, divisions, transcendentals, comparisons/selects, branches, projections and unprojections, all multiplied
// through loops with constant trip counts; plus per-variant sums and estimated bytes read per pixel.
//
// The walker reads the SPIR-V words itself (SPIRV-Tools' opt IR headers are not installed on Debian 12,
// only libspirv.h): it relies on structured control flow (OpLoopMerge) and on the unoptimised code glslang
// emits (compile::compile_program runs with the optimiser off): `for (int k = A; k < B; k += C)` becomes a
// Function-storage int stored A before the loop, loaded and compared with OpSLessThan against B in the
// loop's condition block, and re-stored as OpIAdd(load, C) in the continue block (OpPhi also works).
// Counts are upper bounds: a branch that skips work inside a loop (`continue` on off-screen taps) does
// not reduce them; both sides of every selection are counted.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "shadergen/bindings.h"

namespace aovar::analyze {

// Texture reads are counted per sampler binding of the template contract (shadergen/bindings.h): depth,
// normal, position, AO input, history, prefilter. -1 collects reads whose image the walker cannot resolve.
using shadergen::binding::kDepth;
using shadergen::binding::kHistory;
using shadergen::binding::kInput;
using shadergen::binding::kNormal;
using shadergen::binding::kPosition;
using shadergen::binding::kPrefilter;

struct LoopInfo {
  std::string function;   // OpName of the enclosing function (mangled by glslang: "main(", "f(vf2;")
  int depth = 0;          // nesting depth inside its function (0 = outermost)
  bool constant = false;  // trip count resolved
  long long trips = 1;    // constant: the trip count; dynamic: 1 (counted once)
  bool unroll_hint = false, dont_unroll_hint = false;  // OpLoopMerge loop control
  // A loop found in the module is never unrolled (glslang unrolled loops leave no OpLoopMerge).
};

struct ProgramCost {
  std::map<int, double> fetches;  // binding -> texture reads (sample, fetch, gather, read) per pixel
  double alu = 0;                 // arithmetic, conversion, bit, vector and GLSL.std.450 instructions
  double fma = 0;                 // GLSL.std.450 Fma
  double div = 0;                 // OpFDiv, OpSDiv, OpUDiv and the remainder/modulo ops
  double transcendental = 0;      // Exp Exp2 Log Log2 Pow Sqrt InverseSqrt Sin Cos Tan Asin Acos Atan Atan2 (+ hyperbolic)
  double normalize_length = 0;    // Normalize, Length, Distance (a hidden sqrt each; not in transcendental)
  double cmp_select = 0;          // comparisons, logical ops, OpSelect, Any/All, IsNan/IsInf
  double branches = 0;            // OpBranchConditional, OpSwitch
  double calls = 0;               // OpFunctionCall
  double unprojections = 0;       // calls to ao_view_position_from_depth (texture -> view space)
  double projections = 0;         // calls to ao_uv_from_view_position (view space -> screen uv)
  double position_calls = 0;      // calls to ao_position (buffer read or unprojection, per the position axis)
  std::vector<LoopInfo> loops;    // every loop left in the module (reachable from the entry point or not)
  bool upper_bound = true;        // always: skipped branches are counted
  std::string error;              // non-empty when the module could not be analysed

  double fetch(int binding) const {
    auto it = fetches.find(binding);
    return it == fetches.end() ? 0.0 : it->second;
  }
  double total_fetches() const;
  bool has_dynamic_loop() const;
  ProgramCost& operator+=(const ProgramCost& o);  // sums counts and appends loops
  ProgramCost scaled(double k) const;              // counts times k (loops unchanged)
};

// Throws std::runtime_error for words that are not a SPIR-V module.
ProgramCost analyze_spirv(const std::vector<std::uint32_t>& words);

// Estimated bytes read per pixel: sum over bindings of fetches x bytes per texel (unknown bindings: 0).
double bytes_per_pixel(const std::map<int, double>& fetches, const std::map<int, int>& bytes_per_texel);
// Bytes per texel of a variant's G-buffer bindings from its axes: depth r16f 2 / r32f 4, normals rgb8
// (stored rgba8) 4 / rg8 and oct16 2 / depth 0, position rgba32f 16, AO input and history 4 (r32f or rgba8),
// prefilter 4 (r32f).
std::map<int, int> binding_bytes(const std::string& depth_format, const std::string& normals);

// `aovar analyze --in DIR`: DIR holds variants.json and vulkan/<program>.spv (generate --emit index,spirv).
struct ProgramRow {
  std::string key;
  std::string same_as;  // program whose SPIR-V this one shares ("" when it has its own file)
  ProgramCost cost;
};
struct VariantRow {
  std::string key;
  std::map<std::string, std::string> passes;  // pass -> program key (fragment stages)
  ProgramCost ao;      // the AO pass program
  ProgramCost total;   // every fragment program of its passes, once each (AO-resolution passes not scaled)
  double ao_bytes = 0, total_bytes = 0;
};
struct Analysis {
  std::vector<ProgramRow> programs;
  std::vector<VariantRow> variants;
};
Analysis analyze_folder(const std::filesystem::path& dir);
std::string analysis_json(const Analysis& a);  // the contents of DIR/analysis.json
std::string program_table(const Analysis& a);  // the per-program table the CLI prints

}  // namespace aovar::analyze
