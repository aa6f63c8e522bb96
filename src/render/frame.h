#pragma once
// The AOFrame uniform block (docs/template-contract.md) as the CPU fills it, for either clip convention.
#include <cstdint>

#include <glm/glm.hpp>

#include "passplan/extent.h"
#include "scene/scene.h"

namespace aovar::render {

using passplan::ao_extent;  // size of the AO pass for a resolution factor
using passplan::Extent;

// Clip-space depth range of the API: Vulkan [0, 1], OpenGL [-1, 1]. Both backends use the same y direction
// (NDC y = -1 is render-target row 0), so uv (0, 0) is texel (0, 0) everywhere, uv_to_ndc is the same and
// read-back images have row 0 at the bottom of the view on both.
enum class ClipDepth { zero_to_one, minus_one_to_one };

// std140 layout of `AOFrame`: 3 mat4, 5 vec4, 1 ivec4 = 288 bytes.
struct FrameBlock {
  glm::mat4 view;
  glm::mat4 proj;
  glm::mat4 inv_proj;
  glm::vec4 proj_info;
  glm::vec4 uv_to_ndc;
  glm::vec4 full_size;
  glm::vec4 ao_size;
  glm::vec4 clip;
  glm::ivec4 frame_index;
};
static_assert(sizeof(FrameBlock) == 288, "AOFrame is 288 bytes in std140");

struct FrameSetup {
  const scene::View* view = nullptr;
  int frame = 0;         // frame number: progressive parity (frame & 1) and camera path position
  bool static_camera = false;  // true: stay on path frame 0; false: path frame (frame mod path_frames)
  float radius = 1.0f;   // world-space AO radius
};

// Linear depth of the background: what the G-buffer clears linear depth to (kClearFar, plan.h), what it clamps
// written depth to, and what the shaders get as frame.clip.y. It is the far plane, capped at 65504, the
// largest finite half float, so that it is finite in every depth format and in the shaders' arithmetic:
//  - far = inf (an infinite projection) would store +inf in r16f/r32f, and every method reading a
//    background neighbour would then form inf - inf or 0 * inf (NaN) in its position and depth maths;
//  - a finite far beyond 65504 (e.g. 1e6) already overflows to +inf in r16f.
// Capping makes r16f and r32f agree on what is background (depth >= 0.999 of it), keeps SAO's depth key
// (common/key.glsl reads clip.y) finite, and changes nothing for far planes up to 65504 (every scene's own
// views). Measured: with +inf instead, no NaN reached the result, but the atrium's AO moved by up to 1.0
// at pixels next to the sky (tests/stress/test_stress_geometry.cpp, InfiniteFarRendersLikeTheFittedFar).
inline constexpr float kMaxBackgroundDepth = 65504.0f;
float background_depth(float far_plane);

// Camera, sizes and radius of one frame. `ao` is the AO pass extent (ao_extent of the variant). A view's
// far plane may be +inf: the projection is then the limit far -> inf of the finite one (infinite
// perspective) in either clip convention, and clip.y is background_depth(inf), the finite cap.
FrameBlock make_frame_block(const FrameSetup& setup, Extent full, Extent ao, ClipDepth clip_depth);

}  // namespace aovar::render
