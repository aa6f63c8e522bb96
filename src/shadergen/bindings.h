#pragma once
// The set-0 binding layout every template is written against (docs/template-contract.md, "Interface"):
// two uniform blocks, then one combined image sampler per G-buffer or pass input. The planner routes
// textures to these bindings, both backends bind them, and the static analyser counts texture reads per
// sampler binding. Header-only with no includes, so that any module may use it (analyze links only util).
namespace aovar::shadergen::binding {

inline constexpr int kFrame = 0;      // AOFrame: camera and sizes, shared by every pass
inline constexpr int kParams = 1;     // AOParams: the pass's parameters
inline constexpr int kDepth = 2;      // ao_depth_tex: linear depth
inline constexpr int kNormal = 3;     // ao_normal_tex: view-space normal (absent for normals = depth)
inline constexpr int kPosition = 4;   // ao_position_tex: view-space position (position = position only)
inline constexpr int kInput = 5;      // ao_input_tex: AO input of blur / progressive / upsample
inline constexpr int kHistory = 6;    // ao_history_tex: the previous frame's half (progressive average)
inline constexpr int kPrefilter = 7;  // ao_prefilter_tex: a method's own input (blurred depth, z MIP chain)

inline constexpr int kFirstSampler = kDepth;             // samplers are bindings kFirstSampler .. kCount - 1
inline constexpr int kCount = kPrefilter + 1;            // every binding of the set
inline constexpr int kSamplerCount = kCount - kFirstSampler;

// Trace builds only (issue 33, trace/instrument.h): a storage buffer the instrumented fragment program writes
// its texel reads to. Outside the set above: no shipped program declares it, and the analyser never sees it.
inline constexpr int kTrace = kCount;

constexpr bool is_sampler(int b) { return b >= kFirstSampler && b < kCount; }

// The names GLSL ES 3.00 programs are bound by (it has no binding qualifiers): block names, then sampler names.
constexpr const char* name(int b) {
  constexpr const char* kNames[kCount] = {"AOFrame",         "AOParams",       "ao_depth_tex",
                                          "ao_normal_tex",   "ao_position_tex", "ao_input_tex",
                                          "ao_history_tex",  "ao_prefilter_tex"};
  return b >= 0 && b < kCount ? kNames[b] : "";
}

}  // namespace aovar::shadergen::binding
