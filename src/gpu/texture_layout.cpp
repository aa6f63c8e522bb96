#include "gpu/texture_layout.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace aovar::gpu {

namespace {

constexpr uint64_t kLevelAlignment = 64 * 1024;

uint32_t log2_of_texel_size(int bytes, const std::string& name) {
  for (uint32_t s = 0; s <= 4; ++s)
    if (bytes == 1 << s) return s;
  throw std::invalid_argument("fetch trace: texture '" + name + "' has " + std::to_string(bytes) +
                              " bytes per texel; the layout takes 1, 2, 4, 8 or 16");
}

}  // namespace

TextureLayout::TextureLayout(const std::vector<TracedTexture>& textures) {
  uint64_t next = 0;
  std::array<bool, kMaxTraceSlots> seen{};
  for (const TracedTexture& t : textures) {
    const std::string what = "fetch trace: texture '" + t.name + "'";
    if (t.slot < 0 || t.slot >= kMaxTraceSlots) throw std::invalid_argument(what + " has slot " + std::to_string(t.slot));
    if (seen[t.slot]) throw std::invalid_argument(what + ": slot " + std::to_string(t.slot) + " is used twice");
    seen[t.slot] = true;
    if (t.width < 1 || t.height < 1 || t.width > kMaxTraceExtent || t.height > kMaxTraceExtent)
      throw std::invalid_argument(what + " is " + std::to_string(t.width) + "x" + std::to_string(t.height));
    if (t.levels < 1 || t.levels > kMaxTraceLevels)
      throw std::invalid_argument(what + " has " + std::to_string(t.levels) + " levels");
    const uint32_t shift = log2_of_texel_size(t.bytes_per_texel, t.name);
    for (int lod = 0; lod < t.levels; ++lod) {
      Level& l = levels_[t.slot * kMaxTraceLevels + lod];
      l.width = std::max(1, t.width >> lod);
      l.height = std::max(1, t.height >> lod);
      l.tiles_per_row = (l.width + kTile - 1) / kTile;
      l.bpp_shift = shift;
      l.base = next;
      const uint64_t tiles = uint64_t(l.tiles_per_row) * ((l.height + kTile - 1) / kTile);
      next += tiles * (uint64_t(kTile * kTile) << shift);
      next = (next + kLevelAlignment - 1) / kLevelAlignment * kLevelAlignment;
    }
  }
  total_bytes_ = next;
}

void TextureLayout::outside(uint32_t packed_read) {
  const TexelRead r = unpack_read(packed_read);
  throw std::out_of_range("fetch trace: read of texel (" + std::to_string(r.x) + ", " + std::to_string(r.y) +
                          ") at level " + std::to_string(r.lod) + " of slot " + std::to_string(r.slot) +
                          " is outside every traced texture");
}

}  // namespace aovar::gpu
