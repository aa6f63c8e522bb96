#include "frame_block.h"

#include <cstring>

namespace render_variant {

shaders::FrameBlock still_frame(const std::array<unsigned char, 288>& file_block, const shaders::Plan& plan,
                                shaders::Extent full, int frame) {
  shaders::FrameBlock b;
  static_assert(sizeof b == 288, "AOFrame is 288 bytes in std140");
  std::memcpy(&b, file_block.data(), sizeof b);
  const shaders::Extent ao = shaders::ao_extent(full, plan.resolution);
  // Spelled as aovar's renderer computes them (render::make_frame_block), in float, in this order: the same bits.
  b.ao_size[0] = float(ao.width);
  b.ao_size[1] = float(ao.height);
  b.ao_size[2] = 1.0f / ao.width;
  b.ao_size[3] = 1.0f / ao.height;
  const float p11 = b.proj[1 * 4 + 1];  // proj[1][1], column-major
  b.clip[3] = p11 * 0.5f * float(ao.height);  // pixels per world unit at z = 1 on the AO target
  b.frame_index[0] = frame;
  b.frame_index[1] = frame & 1;  // which half a progressive variant renders
  b.frame_index[2] = b.frame_index[3] = 0;
  return b;
}

}  // namespace render_variant
