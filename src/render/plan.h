#pragma once
// A variant's AO pipeline as a small render graph that every backend executes the same way: textures
// (formats, sizes, clears) and an ordered list of draws (programs, parameter blocks, inputs, outputs).
// All the knowledge of what a variant's axes mean for rendering lives here, not in the backends.
//
//   gbuffer (scene geometry, depth test) -> depth [+ normal] [+ position]        full resolution
//   prefilter   method-specific inputs of the AO pass, read at binding::kPrefilter: AO resolution
//                 unsharp: depth Gaussian, 2 draws (axis 0, 1) -> depth_blur (r32f)
//                 sao: camera-space z pyramid, one draw per MIP level -> zmip (r32f, kZmipLevels levels)
//                 depth_mip = on (the methods whose [algorithms.*] reads name it): the same pyramid (pass depth_mip)
//   ao          fullscreen -> ao_half[parity]                                    AO resolution
//   progressive fullscreen: ao_half[parity] + ao_half[1 - parity] -> ao_avg       AO resolution
//   blur        separable: 2 draws (axis 0, 1) via blur_tmp; bilateral: 1 draw   AO resolution
//               (pass blur_keyed for methods whose AO output packs the depth key: rgba8 AO chain)
//   upsample    fullscreen -> ao_full (depth-aware)                               full resolution
//
// The last draw's output is the result; it is R32F so NaN and Inf survive to the read-back.
//
// Background pixels skip the fragment shader (runtime skipping): the fullscreen draws whose shaders write a
// constant 1 on background (ao, progressive, the unkeyed blurs, upsample) are depth-tested so that the
// rasteriser rejects background pixels before shading; their outputs are cleared to 1 first, which is
// exactly what the shaders' own early-out writes there. The test reads a depth buffer that says
// "background" with the value 1.0:
//   full resolution: the G-buffer's depth buffer (cleared to 1.0; only pixels no triangle covered keep it);
//   AO resolution:   a mask drawn by the manifest's `background_mask` pass, which writes 1.0 where the
//                    depth texel the AO pass reads holds the background (without that pass: no skipping at
//                    reduced resolution, the shaders' early-out still applies).
// Fullscreen triangles lie at depth 1.0 and pass where the stored depth is NOT_EQUAL to it.
#include <array>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "compile/generate.h"
#include "render/frame.h"
#include "shadergen/bindings.h"

namespace aovar::render {

enum class Format { r16f, r32f, rgba8, rg8, rgba32f };
const char* format_name(Format f);
int format_bytes(Format f);

struct Texture {
  std::string name;
  Format format = Format::r16f;
  bool full_resolution = true;      // else the AO pass extent
  bool double_buffered = false;     // ao_half: frame parity p writes copy p; inputs may read the other
  bool cleared = false;             // cleared to `clear` at the start of each frame (G-buffer targets)
  std::array<float, 4> clear{0, 0, 0, 0};  // may use kClearFar (replaced by background_depth(far), frame.h)
  int levels = 1;                   // MIP levels; level l is max(1, extent >> l)
};
inline constexpr float kClearFar = -12345.0f;   // placeholder: +background_depth(far), finite for far = inf
inline constexpr float kClearNegFar = -54321.0f;  // placeholder: -background_depth(far)

struct TextureRef {
  int texture = -1;
  bool previous = false;  // double-buffered texture: the copy written in the previous frame
  int level = -1;         // input: -1 = every level, l = level l alone (read as level 0); output: -1 = level 0
};

struct Shader {
  std::string program_key;          // e.g. "alchemy-s08-p0-nrg8-zdep-rst-hp.frag"
  variants::StageKind stage = variants::StageKind::fragment;
  std::vector<std::uint32_t> spirv;  // Vulkan SPIR-V (the vulkan target's backend)
  std::string glsl;                  // GLSL source (the GL targets' backends)
};

// Depth buffers (D32F) draws test against; never sampled.
struct DepthBuffer {
  std::string name;               // "zbuffer" (the G-buffer's), "background_mask"
  bool full_resolution = true;    // else the AO pass extent
};

enum class DepthUse {
  none,
  geometry,         // clear to 1.0, test LESS, write (the G-buffer)
  write_mask,       // clear to 0.0, test ALWAYS, write: the fullscreen triangle's 1.0 where the shader keeps going
  skip_background,  // test NOT_EQUAL against the triangle's 1.0, no write: pixels holding 1.0 are not shaded
};
const char* depth_use_name(DepthUse u);

struct Draw {
  std::string name;   // "gbuffer", "ao", "progressive", "blur.h", "blur.v", "blur", "upsample"
  std::string pass;   // timing group: the manifest pass name ("blur" for both separable draws)
  bool geometry = false;  // draw the scene's triangles with a depth test; else a fullscreen triangle
  int vertex = -1, fragment = -1;   // indices into PipelinePlan::shaders
  std::vector<float> params;        // AOParams contents (std140: consecutive floats), empty = no block
  std::vector<std::pair<int, TextureRef>> inputs;  // (sampler binding, texture): shadergen/bindings.h
  std::vector<TextureRef> outputs;  // colour attachment per location (texture -1 = location unused)
  bool full_resolution = true;      // viewport: full output or AO extent
  int level = 0;                    // MIP level every output is written at (viewport shrinks with it)
  DepthUse depth = DepthUse::none;
  int depth_buffer = -1;            // index into PipelinePlan::depth_buffers (with depth != none)
  // Trace builds only (trace/trace.h): 32-bit words of the storage buffer bound at binding::kTrace for this
  // draw, 0 = not traced. Word 0 counts pixels whose reads overflowed; the reads follow. Vulkan only.
  std::int64_t trace_words = 0;
};

inline constexpr int kZmipLevels = 6;  // SAO's z pyramid: levels 0..5 (McGuire et al. 2012, §3: MAX_MIP_LEVEL 5)

struct PipelinePlan {
  std::string variant;  // key
  std::map<std::string, std::string> axes;  // axis name -> value (collapsed axes get the manifest's first)
  double resolution = 1.0;
  bool progressive = false;
  std::vector<Shader> shaders;
  std::vector<Texture> textures;
  std::vector<Draw> draws;
  std::vector<DepthBuffer> depth_buffers;
  int result = -1;  // texture holding the final AO (full resolution, R32F)

  std::vector<std::string> passes() const;  // timing groups in draw order, unique
};

// Parameter values by "<pass>.<name>" (e.g. "ao.intensity", "blur.radius_px"); missing = manifest default.
using ParamOverrides = variants::ParamValues;

// Builds the plan of variant `variant` (index into compiled.space.variants) for `target` (vulkan: SPIR-V,
// gl45: GLSL source). `compiled` must hold successful builds for that target. Throws std::runtime_error
// for a renderer-set block member the renderer does not know, and (when `strict`) for an override naming
// no parameter of this variant; callers planning many variants check overrides with parameter_keys().
PipelinePlan plan_pipeline(const compile::CompiledSpace& compiled, int variant, variants::Target target,
                           const ParamOverrides& overrides = {}, bool strict = true);

// "<pass>.<name>" of every manifest parameter the variant's passes take.
std::vector<std::string> parameter_keys(const compile::CompiledSpace& compiled, int variant);

// The plan cut after draw `last_draw` (e.g. "ao"), whose output becomes the result (single-buffered,
// R32F): for reading intermediate passes, e.g. one progressive half, in tests and stress checks.
// Throws std::runtime_error when the plan has no such draw.
PipelinePlan plan_prefix(const PipelinePlan& plan, const std::string& last_draw);

// Throws BackendError (render/backend.h) "<backend>: plan of <variant> is malformed: <what>" for a plan no
// backend can execute: a bug in the planner or a hand-built test plan, not user input. Both backends call
// it on the plan_for_size plan they prepare.
void validate_plan(const PipelinePlan& plan, std::string_view backend);

// The plan at one frame size: a MIP chain cannot have more levels than its texture's extent allows
// (floor(log2(max(w, h))) + 1; SAO's 6-level z pyramid at 24x14, quarter resolution of 96x54, has 5), so
// each texture keeps at most that many and the draws into the missing levels go. Shaders never read them:
// on-screen taps choose levels below log2 of the AO target's diagonal. Backends prepare this, not the plan.
PipelinePlan plan_for_size(const PipelinePlan& plan, Extent size);

// The index of the first draw named `name` in the plan that runs at `size` (plan_for_size), which is what
// Backend::render's times and Backend::set_params's `draw` index: the full plan's index is another draw
// wherever plan_for_size dropped MIP draws before it (SAO at 8x8). Throws std::runtime_error naming the
// variant when that plan has no such draw.
std::size_t draw_index_at_size(const PipelinePlan& plan, Extent size, std::string_view name);

// The plan without runtime skipping: no background mask, no depth-tested fullscreen draws, every background
// pixel shaded (and sent through the shaders' early-out). Produces the same image; for measuring what the
// skipping saves.
PipelinePlan plan_without_background_skip(const PipelinePlan& plan);

// A progressive plan whose average reads this frame's half twice instead of the previous frame's other half:
// what one frame alone shows (after a camera cut, or without history). Other plans come back unchanged.
PipelinePlan plan_single_frame(const PipelinePlan& plan);

}  // namespace aovar::render
