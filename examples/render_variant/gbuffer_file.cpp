#include "gbuffer_file.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "errors.h"

namespace render_variant {
namespace {

constexpr char kMagic[8] = {'A', 'O', 'V', 'A', 'R', 'G', 'B', '1'};
constexpr std::size_t kHeaderBytes = 8 + 4 * 4 + 288;  // magic, width, height, plane count, reserved, AOFrame
constexpr std::size_t kPlaneHeaderBytes = 48;          // name, format, bytes per texel, reserved
constexpr std::uint32_t kMaxPlanes = 16;               // the gbuffer draw writes at most three, plus its depth buffer
constexpr std::uint32_t kMaxSide = 1u << 15;           // beyond any Vulkan device's image size

const char* const kRegenerate =
    "write it again with `aovar gbuffer --scene S --view V --variant KEY --size WxH --out FILE`";

// Reads the file's bytes in a cursor that refuses to run past the end.
class Reader {
 public:
  Reader(const std::string& path, std::vector<unsigned char> bytes) : path_(path), bytes_(std::move(bytes)) {}

  const unsigned char* take(std::size_t n, const char* what) {
    if (bytes_.size() - at_ < n)
      throw InputError(path_ + ": truncated G-buffer file (" + std::to_string(bytes_.size()) + " bytes, ends inside " +
                       what + "): " + kRegenerate);
    const unsigned char* p = bytes_.data() + at_;
    at_ += n;
    return p;
  }
  // Little-endian on every host: the file's byte order, not the machine's.
  std::uint32_t u32(const char* what) {
    const unsigned char* p = take(4, what);
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
  }
  // A 16-byte ASCII field, NUL-padded.
  std::string text16(const char* what) {
    const unsigned char* p = take(16, what);
    std::size_t n = 0;
    while (n < 16 && p[n] != 0) ++n;
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  std::size_t left() const { return bytes_.size() - at_; }

 private:
  std::string path_;
  std::vector<unsigned char> bytes_;
  std::size_t at_ = 0;
};

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(path + ": cannot open the G-buffer file: check the path (" + kRegenerate + ")");
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

Plane read_plane(Reader& r, const GbufferFile& g, std::uint32_t index) {
  const std::string where = "plane " + std::to_string(index);
  Plane p;
  p.name = r.text16("a plane header");
  p.format = r.text16("a plane header");
  p.bytes_per_texel = r.u32("a plane header");
  r.take(12, "a plane header");  // reserved
  const std::uint32_t expected = texel_bytes(p.format);
  if (expected == 0)
    throw InputError(g.path + ": " + where + " (" + p.name + ") has the unknown format '" + p.format +
                     "' (r16f, r32f, rgba8, rg8, rgba32f or d32f): " + kRegenerate);
  if (p.bytes_per_texel != expected)
    throw InputError(g.path + ": " + where + " (" + p.name + ", " + p.format + ") says " +
                     std::to_string(p.bytes_per_texel) + " bytes per texel, the format has " + std::to_string(expected) +
                     ": " + kRegenerate);
  const std::size_t bytes = std::size_t(g.width) * g.height * p.bytes_per_texel;
  const unsigned char* texels = r.take(bytes, ("the texels of " + where).c_str());
  p.texels.assign(texels, texels + bytes);
  return p;
}

}  // namespace

std::uint32_t texel_bytes(const std::string& format) {
  if (format == "r16f" || format == "rg8") return 2;
  if (format == "r32f" || format == "rgba8" || format == "d32f") return 4;
  if (format == "rgba32f") return 16;
  return 0;
}

const Plane* GbufferFile::find(const std::string& name) const {
  for (const Plane& p : planes)
    if (p.name == name) return &p;
  return nullptr;
}

GbufferFile read_gbuffer_file(const std::string& path) {
  GbufferFile g;
  g.path = path;
  Reader r(path, file_bytes(path));
  if (r.left() < kHeaderBytes || std::memcmp(r.take(8, "the magic"), kMagic, 8) != 0)
    throw InputError(path + ": not a G-buffer file (no AOVARGB1 magic, or shorter than its " +
                     std::to_string(kHeaderBytes) + "-byte header): " + kRegenerate);
  g.width = r.u32("the header");
  g.height = r.u32("the header");
  const std::uint32_t count = r.u32("the header");
  r.u32("the header");  // reserved
  if (g.width == 0 || g.height == 0 || g.width > kMaxSide || g.height > kMaxSide)
    throw InputError(path + ": frame size " + std::to_string(g.width) + "x" + std::to_string(g.height) +
                     " is out of range (1.." + std::to_string(kMaxSide) + " per side): " + kRegenerate);
  if (count == 0 || count > kMaxPlanes)
    throw InputError(path + ": " + std::to_string(count) + " planes (1.." + std::to_string(kMaxPlanes) +
                     " expected): " + kRegenerate);
  std::memcpy(g.frame.data(), r.take(g.frame.size(), "the AOFrame block"), g.frame.size());
  for (std::uint32_t i = 0; i < count; ++i) {
    Plane p = read_plane(r, g, i);
    if (g.find(p.name))
      throw InputError(path + ": two planes are named '" + p.name + "': " + kRegenerate);
    g.planes.push_back(std::move(p));
  }
  if (r.left() != 0)
    throw InputError(path + ": " + std::to_string(r.left()) + " bytes after the last plane (size mismatch): " +
                     kRegenerate);
  return g;
}

}  // namespace render_variant
