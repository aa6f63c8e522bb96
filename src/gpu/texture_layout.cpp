#include "gpu/texture_layout.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace aovar::gpu {

namespace {

constexpr uint64_t kLevelAlignment = 64 * 1024;

// Bits of a 6-bit coordinate spread to the even bit positions (x) of a 12-bit Morton index.
constexpr std::array<uint32_t, TextureLayout::kTile> spread_table() {
  std::array<uint32_t, TextureLayout::kTile> t{};
  for (uint32_t v = 0; v < t.size(); ++v)
    for (int b = 0; b < 6; ++b) t[v] |= ((v >> b) & 1u) << (2 * b);
  return t;
}
constexpr auto kSpread = spread_table();

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

uint64_t TextureLayout::address(uint32_t packed_read) const {
  const uint32_t x = packed_read & 8191u, y = packed_read >> 13 & 8191u;
  const uint32_t lod = packed_read >> 26 & 7u, slot = packed_read >> 29;
  const Level& l = levels_[slot < uint32_t(kMaxTraceSlots) ? slot * kMaxTraceLevels + lod : 0];
  if (slot >= uint32_t(kMaxTraceSlots) || x >= l.width || y >= l.height) {
    const TexelRead r = unpack_read(packed_read);
    throw std::out_of_range("fetch trace: read of texel (" + std::to_string(r.x) + ", " + std::to_string(r.y) +
                            ") at level " + std::to_string(r.lod) + " of slot " + std::to_string(r.slot) +
                            " is outside every traced texture");
  }
  const uint64_t tile = uint64_t(y / kTile) * l.tiles_per_row + x / kTile;
  const uint64_t morton = kSpread[x % kTile] | kSpread[y % kTile] << 1;
  return l.base + ((tile * (kTile * kTile) + morton) << l.bpp_shift);
}

}  // namespace aovar::gpu
