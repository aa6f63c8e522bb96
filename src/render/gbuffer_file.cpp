#include "render/gbuffer_file.h"

#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "passplan/plan.h"

namespace aovar::render {
namespace {

constexpr std::size_t kNameBytes = 16;
constexpr std::size_t kHeaderBytes = 8 + 4 * 4 + sizeof(FrameBlock);
constexpr std::size_t kPlaneHeaderBytes = 2 * kNameBytes + 4 + 4 + 8;
constexpr passplan::Format kFormats[] = {passplan::Format::r16f, passplan::Format::r32f, passplan::Format::rgba8,
                                         passplan::Format::rg8, passplan::Format::rgba32f};

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

void put_name(std::string& out, const std::string& name) {
  if (name.empty() || name.size() >= kNameBytes) throw std::runtime_error(fmt::format("G-buffer plane name '{}': 1 to 15 bytes", name));
  out += name;
  out.append(kNameBytes - name.size(), '\0');
}

// Reads the file front to back; every read checks that the bytes are there.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& what) : bytes_(bytes), what_(what) {}
  std::string_view take(std::size_t n, const char* field) {
    if (bytes_.size() - at_ < n)
      fail(fmt::format("ends inside {} (at byte {} of {})", field, at_, bytes_.size()));
    const std::string_view s = bytes_.substr(at_, n);
    at_ += n;
    return s;
  }
  std::uint32_t u32(const char* field) {
    const std::string_view s = take(4, field);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(static_cast<unsigned char>(s[i])) << (8 * i);
    return v;
  }
  std::string name(const char* field) {
    const std::string_view s = take(kNameBytes, field);
    const std::size_t end = s.find('\0');
    if (end == 0 || end == std::string_view::npos) fail(fmt::format("{} is not a NUL-padded name", field));
    return std::string(s.substr(0, end));
  }
  bool done() const { return at_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(fmt::format("{}: not a G-buffer file aovar can read: {} (write it again with aovar gbuffer)", what_, why));
  }

 private:
  std::string_view bytes_;
  std::string what_;
  std::size_t at_ = 0;
};

}  // namespace

std::uint32_t gbuffer_texel_bytes(std::string_view format) {
  if (format == "d32f") return 4;
  for (passplan::Format f : kFormats)
    if (format == passplan::format_name(f)) return static_cast<std::uint32_t>(passplan::format_bytes(f));
  return 0;
}

std::string encode_gbuffer(const GbufferImage& image) {
  std::string out(kGbufferMagic);
  put_u32(out, static_cast<std::uint32_t>(image.size.width));
  put_u32(out, static_cast<std::uint32_t>(image.size.height));
  put_u32(out, static_cast<std::uint32_t>(image.planes.size()));
  put_u32(out, 0);
  // FrameBlock is std140 floats and ints without padding, and every platform aovar builds on is little-endian.
  out.append(reinterpret_cast<const char*>(&image.frame), sizeof image.frame);
  const std::size_t texels = std::size_t(image.size.width) * image.size.height;
  for (const GbufferPlane& p : image.planes) {
    if (gbuffer_texel_bytes(p.format) != p.texel_bytes || p.texels.size() != texels * p.texel_bytes)
      throw std::runtime_error(fmt::format("G-buffer plane {}: {} bytes of {} at {}x{}", p.name, p.texels.size(),
                                           p.format, image.size.width, image.size.height));
    put_name(out, p.name);
    put_name(out, p.format);
    put_u32(out, p.texel_bytes);
    put_u32(out, 0);
    out.append(8, '\0');
    out += p.texels;
  }
  return out;
}

GbufferImage decode_gbuffer(std::string_view bytes, const std::string& what) {
  Reader in(bytes, what);
  if (in.take(kGbufferMagic.size(), "the magic") != kGbufferMagic) in.fail("its first 8 bytes are not AOVARGB1");
  GbufferImage image;
  const std::uint32_t width = in.u32("the width"), height = in.u32("the height"), planes = in.u32("the plane count");
  in.u32("the reserved word");
  if (width == 0 || height == 0 || width > 16384 || height > 16384)
    in.fail(fmt::format("frame size {}x{} (1 to 16384 a side)", width, height));
  if (planes == 0 || planes > 8) in.fail(fmt::format("{} planes (1 to 8)", planes));
  image.size = {static_cast<int>(width), static_cast<int>(height)};
  std::memcpy(&image.frame, in.take(sizeof(FrameBlock), "the AOFrame block").data(), sizeof(FrameBlock));
  for (std::uint32_t i = 0; i < planes; ++i) {
    GbufferPlane p;
    p.name = in.name("a plane's name");
    p.format = in.name("a plane's format");
    p.texel_bytes = in.u32("a plane's texel size");
    in.take(12, "a plane's reserved bytes");
    if (gbuffer_texel_bytes(p.format) == 0) in.fail(fmt::format("plane {} has the unknown format '{}'", p.name, p.format));
    if (p.texel_bytes != gbuffer_texel_bytes(p.format))
      in.fail(fmt::format("plane {}: {} bytes a texel for {}", p.name, p.texel_bytes, p.format));
    p.texels = std::string(in.take(std::size_t(width) * height * p.texel_bytes, "a plane's texels"));
    image.planes.push_back(std::move(p));
  }
  if (!in.done()) in.fail("bytes after the last plane");
  static_assert(kHeaderBytes == 312 && kPlaneHeaderBytes == 48, "the layout docs/template-contract.md gives");
  return image;
}

}  // namespace aovar::render
