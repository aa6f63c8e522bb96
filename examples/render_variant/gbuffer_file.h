#pragma once
// Reads the G-buffer file `aovar gbuffer` writes (docs/template-contract.md, "The G-buffer file"): what a
// variant's `gbuffer` draw leaves for one view at one frame size, and that frame's AOFrame block.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace render_variant {

// One plane: a plan texture the gbuffer draw writes (depth, normal, position) or its depth buffer (zbuffer).
struct Plane {
  std::string name;    // "depth", "normal", "position", "zbuffer"
  std::string format;  // "r16f", "r32f", "rgba8", "rg8", "rgba32f", "d32f"
  std::uint32_t bytes_per_texel = 0;
  std::vector<unsigned char> texels;  // width x height texels as the image holds them, rows from the bottom
};

struct GbufferFile {
  std::string path;  // for messages
  std::uint32_t width = 0, height = 0;
  std::array<unsigned char, 288> frame{};  // the AOFrame block (std140) of the view's still frame 0
  std::vector<Plane> planes;

  const Plane* find(const std::string& name) const;  // nullptr when the file has no such plane
};

// Bytes per texel of a plane format, 0 for a name the format does not know.
std::uint32_t texel_bytes(const std::string& format);

// Reads and checks `path`; throws InputError naming the file and what is wrong (missing, wrong magic, truncated,
// a plane whose format or size does not add up, bytes left over).
GbufferFile read_gbuffer_file(const std::string& path);

}  // namespace render_variant
