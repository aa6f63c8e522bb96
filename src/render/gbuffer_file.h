#pragma once
// The G-buffer file (docs/template-contract.md, "The G-buffer file"): what a variant's gbuffer draw leaves for
// one view at one frame size, texels as the images hold them, with the view's AOFrame block. A renderer that
// links only the generated library reads it to run the rest of the plan on exactly what aovar scored
// (examples/render_variant), and the shared G-buffer cache stores its entries in it. A binary file of our own:
// no image format carries half floats, unorm pairs, a depth buffer and a uniform block together, and an engine
// reads this one with a dozen lines of C.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "render/frame.h"

namespace aovar::render {

inline constexpr std::string_view kGbufferMagic = "AOVARGB1";

// One image of the G-buffer: a plan texture the gbuffer draw writes ("depth", "normal", "position") or its
// depth buffer ("zbuffer").
struct GbufferPlane {
  std::string name;    // at most 15 bytes
  std::string format;  // passplan::format_name ("r16f", "rgba8", ...) or "d32f"
  std::uint32_t texel_bytes = 0;
  std::string texels;  // width * height * texel_bytes, rows from the bottom of the view
};

struct GbufferImage {
  Extent size;
  FrameBlock frame{};  // the view's still frame 0 with the AO pass at full resolution
  std::vector<GbufferPlane> planes;
};

// The texel size of a plane format; 0 for a name that is none.
std::uint32_t gbuffer_texel_bytes(std::string_view format);

std::string encode_gbuffer(const GbufferImage& image);
// Throws std::runtime_error, one line naming `what` (the file) and what is wrong: a foreign or truncated file,
// an unknown format, a plane of the wrong size.
GbufferImage decode_gbuffer(std::string_view bytes, const std::string& what);

}  // namespace aovar::render
