#pragma once
// The AOFrame block of each frame of a still, from the one the G-buffer file holds.
#include <array>

#include "shaders.h"

namespace render_variant {

// The file's block (frame 0, filled for an AO pass at full resolution) made frame `frame` of variant plan `plan` at
// frame size `full`: ao_size and clip.w for the plan's AO extent, frame_index {frame, frame & 1, 0, 0}
// (docs/template-contract.md, "The G-buffer file").
shaders::FrameBlock still_frame(const std::array<unsigned char, 288>& file_block, const shaders::Plan& plan,
                                shaders::Extent full, int frame);

}  // namespace render_variant
