#pragma once
// The AOFrame uniform block (docs/template-contract.md) as the CPU fills it, for either clip convention.
#include <cstdint>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace aovar::render {

struct Extent {
  int width = 0, height = 0;
  friend bool operator==(const Extent&, const Extent&) = default;
};

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

// Camera, sizes and radius of one frame. `ao` is the AO pass extent (ao_extent of the variant).
FrameBlock make_frame_block(const FrameSetup& setup, Extent full, Extent ao, ClipDepth clip_depth);

// Size of the AO pass for a resolution factor (1, 0.5, 0.25): rounded up, at least 1.
Extent ao_extent(Extent full, double resolution);

}  // namespace aovar::render
