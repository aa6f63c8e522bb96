#pragma once
// A variant's AO pipeline as data, from its axes alone: textures (formats, resolution, clears, MIP levels), depth
// buffers, and the draws in execution order (the manifest pass whose programs each runs, inputs by sampler
// binding, outputs by location, viewport, depth use, the AOParams members the renderer sets per draw). All the
// knowledge of what a variant's axes mean for rendering lives here, below compile: the renderer adds the compiled
// shaders and parameter values (render/plan.h) and the generated library embeds it (compile/emit_plan.cpp), so a
// generator-only build emits the same plan the renderer runs. docs/template-contract.md is its reference.
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
#include <utility>
#include <vector>

#include "passplan/extent.h"
#include "variants/space.h"

namespace aovar::passplan {

enum class Format { r16f, r32f, rgba8, rg8, rgba32f };
const char* format_name(Format f);
int format_bytes(Format f);

struct Texture {
  std::string name;
  Format format = Format::r16f;
  bool full_resolution = true;      // else the AO pass extent
  bool double_buffered = false;     // ao_half: frame parity p writes copy p; inputs may read the other
  bool cleared = false;             // cleared to `clear` at the start of each frame (G-buffer targets)
  std::array<float, 4> clear{0, 0, 0, 0};  // may use kClearFar (replaced by background_depth(far), render/frame.h)
  int levels = 1;                   // MIP levels; level l is max(1, extent >> l)
};
inline constexpr float kClearFar = -12345.0f;   // placeholder: +background_depth(far), finite for far = inf
inline constexpr float kClearNegFar = -54321.0f;  // placeholder: -background_depth(far)

struct TextureRef {
  int texture = -1;
  bool previous = false;  // double-buffered texture: the copy written in the previous frame
  int level = -1;         // input: -1 = every level, l = level l alone (read as level 0); output: -1 = level 0
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

inline constexpr int kZmipLevels = 6;  // SAO's z pyramid: levels 0..5 (McGuire et al. 2012, §3: MAX_MIP_LEVEL 5)

// What a draw reads and writes, where and how it tests depth: the same in the pass plan and in the renderer's
// executable plan (render::Draw), which adds its shaders and parameter values.
struct DrawIo {
  std::string name;   // "gbuffer", "ao", "progressive", "blur.h", "blur.v", "blur", "upsample", "zmip.3", ...
  std::string pass;   // timing group: the manifest pass name ("blur" for both separable draws, "prefilter")
  bool geometry = false;  // draw the scene's triangles with a depth test; else a fullscreen triangle
  std::vector<std::pair<int, TextureRef>> inputs;  // (sampler binding, texture): shadergen/bindings.h
  std::vector<TextureRef> outputs;  // colour attachment per location (texture -1 = location unused)
  bool full_resolution = true;      // viewport: full output or AO extent
  int level = 0;                    // MIP level every output is written at (viewport shrinks with it)
  DepthUse depth = DepthUse::none;
  int depth_buffer = -1;            // index into the plan's depth_buffers (with depth != none)
};

// An AOParams member the renderer sets per draw rather than the manifest: the separable passes' `axis`
// (0 horizontal, 1 vertical), a pyramid draw's `level`.
struct Uniform {
  std::string name;
  float value = 0;
};

struct PassDraw : DrawIo {
  int program_pass = -1;          // index into Manifest::passes: the pass whose programs and parameters it runs
  std::vector<Uniform> uniforms;  // renderer-set AOParams members
};

// What every plan of a variant holds besides its draws.
struct PlanResources {
  std::string variant;  // key
  std::map<std::string, std::string> axes;  // axis name -> value (collapsed axes get the manifest's first)
  double resolution = 1.0;
  bool progressive = false;
  std::vector<Texture> textures;
  std::vector<DepthBuffer> depth_buffers;
  int result = -1;  // texture holding the final AO (full resolution, R32F)
};

struct PassPlan : PlanResources {
  std::vector<PassDraw> draws;
};

// The pass plan of variant `variant` (an index into space.variants). Throws std::runtime_error for a manifest
// that lacks a pass the variant's axes need (gbuffer, ao, progressive, upsample, depth_mip).
PassPlan plan_passes(const variants::Manifest& manifest, const variants::VariantSpace& space, int variant);

// Whether draw `d` of a plan runs at frame size `full` (mip_levels_at, passplan/extent.h): a draw writing a
// MIP level its texture cannot have at that size is skipped. Shaders never read those levels: on-screen taps
// choose levels below log2 of the AO target's diagonal.
bool draw_runs_at(const PlanResources& plan, const DrawIo& d, Extent full);
// The levels texture `t` keeps at frame size `full`.
int levels_at(const PlanResources& plan, const Texture& t, Extent full);

}  // namespace aovar::passplan
