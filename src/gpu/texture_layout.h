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

namespace layout_detail {
// Bits of a 6-bit coordinate spread to the even bit positions of a 12-bit Morton index.
constexpr std::array<uint32_t, 64> spread_table() {
  std::array<uint32_t, 64> t{};
  for (uint32_t v = 0; v < t.size(); ++v)
    for (int b = 0; b < 6; ++b) t[v] |= ((v >> b) & 1u) << (2 * b);
  return t;
}
inline constexpr std::array<uint32_t, 64> kSpread = spread_table();
}  // namespace layout_detail

class TextureLayout {
 public:
  // Throws std::invalid_argument for a slot outside 0..kMaxTraceSlots-1, a slot twice, a size outside
  // 1..kMaxTraceExtent, levels outside 1..kMaxTraceLevels or bytes per texel that are not 1, 2, 4, 8 or 16.
  explicit TextureLayout(const std::vector<TracedTexture>& textures);

  // The byte address of a read's texel. Throws std::out_of_range for a texture or level the layout does
  // not have, or a texel outside its level.
  uint64_t address(uint32_t packed_read) const {
    const uint32_t x = packed_read & 8191u, y = packed_read >> 13 & 8191u;
    const uint32_t level = (packed_read >> 29) * kMaxTraceLevels + (packed_read >> 26 & 7u);
    if (level >= levels_.size() || x >= levels_[level].width || y >= levels_[level].height) outside(packed_read);
    const Level& l = levels_[level];
    const uint64_t tile = uint64_t(y / kTile) * l.tiles_per_row + x / kTile;
    const uint64_t morton = layout_detail::kSpread[x % kTile] | layout_detail::kSpread[y % kTile] << 1;
    return l.base + ((tile * (kTile * kTile) + morton) << l.bpp_shift);
  }
  uint64_t address(const TexelRead& r) const { return address(pack_read(r)); }

  // Bytes from address 0 to the end of the last level: every address is below it.
  uint64_t total_bytes() const { return total_bytes_; }

  static constexpr int kTile = 64;  // tile edge, texels

 private:
  [[noreturn]] static void outside(uint32_t packed_read);

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
