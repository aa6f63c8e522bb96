#pragma once
// The texel fetches of one draw of a pass, per output pixel and per tap in issue order (issue 33): what a
// trace build of the real shaders records on the Vulkan backend, and what the cache simulator (gpu/cache_sim.h)
// replays in a GPU's order. Pure data: no rendering here.
#include <cstdint>
#include <string>
#include <vector>

namespace aovar::gpu {

// One texture a traced draw reads. `slot` is the id packed into each read (0..6).
struct TracedTexture {
  std::string name;         // the sampler's name in the template ("ao_depth_tex")
  int slot = 0;
  int width = 0, height = 0;  // level 0, texels
  int levels = 1;             // MIP levels
  int bytes_per_texel = 4;    // of the plan's format (r16f 2, r32f 4, rgba8 4, rgba16f 8, rgba32f 16)
};

// One texel read: texture slot, MIP level and texel coordinates at that level.
struct TexelRead {
  int slot = 0, lod = 0, x = 0, y = 0;
  bool operator==(const TexelRead&) const = default;
};

// A read packs into 32 bits: x 13 bits, y 13 bits, lod 3 bits, slot 3 bits (7 is unused, so the all-ones
// word is never a read). Frames up to 8192 texels wide.
inline constexpr uint32_t kNoRead = 0xFFFFFFFFu;
inline constexpr int kMaxTraceExtent = 8192;
inline constexpr int kMaxTraceSlots = 7;
inline constexpr int kMaxTraceLevels = 8;

inline uint32_t pack_read(const TexelRead& r) {
  return uint32_t(r.x) | uint32_t(r.y) << 13 | uint32_t(r.lod) << 26 | uint32_t(r.slot) << 29;
}
inline TexelRead unpack_read(uint32_t w) {
  return {int(w >> 29), int(w >> 26 & 7u), int(w & 8191u), int(w >> 13 & 8191u)};
}

// The reads of one draw over a rectangle of its output pixels (the whole frame, or a window of it where a
// reduced trace is enough). Pixel (x, y) is in framebuffer coordinates (gl_FragCoord, y = 0 at the top on
// Vulkan); slot i of pixel p holds its i-th read in issue order, kNoRead after its last.
struct FetchTrace {
  std::string pass;                    // manifest pass ("ao", "blur", ...)
  int draw = 0;                        // index of the draw within the pass
  int plan_draw = -1;                  // index of the draw in its variant's render plan
  int frame_width = 0, frame_height = 0;  // the draw's output extent
  int x0 = 0, y0 = 0, width = 0, height = 0;  // the traced rectangle
  int max_taps = 0;                    // slots per pixel
  std::vector<TracedTexture> textures;
  std::vector<uint32_t> reads;         // ((y - y0) * width + (x - x0)) * max_taps + tap
  int64_t overflowed_pixels = 0;       // pixels with more reads than max_taps (their tail is lost)

  const uint32_t* pixel(int x, int y) const {
    return reads.data() + (int64_t(y - y0) * width + (x - x0)) * max_taps;
  }
  // Reads recorded for pixel (x, y): slots before the first kNoRead.
  int reads_of(int x, int y) const {
    const uint32_t* p = pixel(x, y);
    int n = 0;
    while (n < max_taps && p[n] != kNoRead) ++n;
    return n;
  }
};

}  // namespace aovar::gpu
