#pragma once
// A variant's AO pipeline as the backends execute it: the pass plan (passplan/plan.h: textures, depth buffers,
// draws in order with inputs, outputs, viewports and depth use, from the variant's axes alone) with the compiled
// shaders of one target and each draw's AOParams contents. What an axis means for rendering is decided there,
// below compile, so the generated library carries the same plan (compile/emit_plan.cpp).
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "compile/generate.h"
#include "passplan/plan.h"
#include "render/frame.h"
#include "shadergen/bindings.h"

namespace aovar::render {

using passplan::DepthBuffer;
using passplan::DepthUse;
using passplan::depth_use_name;
using passplan::Format;
using passplan::format_bytes;
using passplan::format_name;
using passplan::kClearFar;
using passplan::kClearNegFar;
using passplan::kZmipLevels;
using passplan::Texture;
using passplan::TextureRef;

struct Shader {
  std::string program_key;          // e.g. "alchemy-s08-p0-nrg8-zdep-rst-hp.frag"
  variants::StageKind stage = variants::StageKind::fragment;
  std::vector<std::uint32_t> spirv;  // Vulkan SPIR-V (the vulkan target's backend)
  std::string glsl;                  // GLSL source (the GL targets' backends)
};

// A pass-plan draw with its shaders and parameter block.
struct Draw : passplan::DrawIo {
  int vertex = -1, fragment = -1;   // indices into PipelinePlan::shaders
  std::vector<float> params;        // AOParams contents (std140: consecutive floats), empty = no block
  // Trace builds only (trace/trace.h): 32-bit words of the storage buffer bound at binding::kTrace for this
  // draw, 0 = not traced. Word 0 counts pixels whose reads overflowed; the reads follow. Vulkan only.
  std::int64_t trace_words = 0;
  // Trace builds only: the pixels of the draw's viewport it shades (x0, y0, width, height; width 0: all of
  // them), for a traced draw no later draw reads, whose pixels outside its window no one would see. Vulkan only.
  std::array<int, 4> scissor{0, 0, 0, 0};
};

struct PipelinePlan : passplan::PlanResources {
  std::vector<Shader> shaders;
  std::vector<Draw> draws;

  std::vector<std::string> passes() const;  // timing groups in draw order, unique
};

// Parameter values by "<pass>.<name>" (e.g. "ao.intensity", "blur.radius_px"); missing = manifest default.
using ParamOverrides = variants::ParamValues;

// Builds the plan of variant `variant` (index into compiled.space.variants) for `target` (vulkan: SPIR-V,
// gl45: GLSL source): passplan::plan_passes with each draw's shaders and AOParams block (compile::block_values:
// the overrides, else the manifest's values, and the draw's uniforms). `compiled` must hold successful builds
// for that target. Throws std::runtime_error for a block member that is neither a parameter nor one of the
// draw's uniforms, and (when `strict`) for an override naming no parameter of this variant; callers planning
// many variants check overrides with parameter_keys().
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
// (passplan::mip_levels_at; SAO's 6-level z pyramid at 24x14, quarter resolution of 96x54, has 5), so each
// texture keeps at most that many and the draws into the missing levels go (passplan::draw_runs_at, the rule
// the generated library states too). Backends prepare this, not the plan.
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
