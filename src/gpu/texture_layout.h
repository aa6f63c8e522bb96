#pragma once
// Where a traced texel lives in GPU memory, for the cache simulator (gpu/cache_sim.h). A stand-in for the
// drivers' tiled ("swizzled") layouts, which keep 2-D neighbourhoods in one cache line: each MIP level is
// cut into 64x64-texel tiles stored one after another in row-major order, and the texels of a tile are in
// Morton (Z) order. So every aligned run of 2^k texels is a 2-D block: a 64-byte line of 4-byte texels
// holds 4x4 texels, a 128-byte line 8x4, a 32-byte line 4x2. Textures are laid out in slot order, their
// levels one after another, each level at a 64 KiB-aligned base address: deterministic, no gaps shared.
#include <array>
#include <cstdint>
#include <vector>

#include "gpu/fetch_trace.h"

namespace aovar::gpu {

class TextureLayout {
 public:
  // Throws std::invalid_argument for a slot outside 0..kMaxTraceSlots-1, a slot twice, a size outside
  // 1..kMaxTraceExtent, levels outside 1..kMaxTraceLevels or bytes per texel that are not 1, 2, 4, 8 or 16.
  explicit TextureLayout(const std::vector<TracedTexture>& textures);

  // The byte address of a read's texel. Throws std::out_of_range for a texture or level the layout does
  // not have, or a texel outside its level.
  uint64_t address(uint32_t packed_read) const;
  uint64_t address(const TexelRead& r) const { return address(pack_read(r)); }

  // Bytes from address 0 to the end of the last level: every address is below it.
  uint64_t total_bytes() const { return total_bytes_; }

  static constexpr int kTile = 64;  // tile edge, texels

 private:
  struct Level {
    uint64_t base = 0;
    uint32_t width = 0, height = 0;  // 0: no such texture or level
    uint32_t tiles_per_row = 0;
    uint32_t bpp_shift = 0;          // log2(bytes per texel)
  };
  std::array<Level, kMaxTraceSlots * kMaxTraceLevels> levels_{};
  uint64_t total_bytes_ = 0;
};

}  // namespace aovar::gpu
