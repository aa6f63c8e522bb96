#include "image/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

// Debian's stb (libstb-dev) is C compiled as C++ here: its struct initialisers trip -Wextra, nothing of ours.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "util/fs.h"

namespace aovar::image {

void write_pfm(const std::filesystem::path& path, const FloatImage& image) {
  // Negative scale = little-endian. PFM stores rows bottom to top, our order.
  std::string out = fmt::format("Pf\n{} {}\n-1.0\n", image.width, image.height);
  std::size_t header = out.size();
  out.resize(header + image.pixels.size() * sizeof(float));
  std::memcpy(out.data() + header, image.pixels.data(), image.pixels.size() * sizeof(float));
  util::write_atomic(path, out);
}

FloatImage read_pfm(const std::filesystem::path& path) {
  auto bytes = util::read_file(path);
  if (!bytes) throw std::runtime_error(fmt::format("{}: error: cannot open", util::display_path(path)));
  FloatImage img;
  char magic[3] = {};
  float scale = 0;
  int consumed = 0;
  if (std::sscanf(bytes->c_str(), "%2s %d %d %f%n", magic, &img.width, &img.height, &scale, &consumed) != 4 ||
      std::string(magic) != "Pf" || img.width <= 0 || img.height <= 0 || scale >= 0)
    throw std::runtime_error(fmt::format("{}: error: not a little-endian greyscale PFM", util::display_path(path)));
  std::size_t start = static_cast<std::size_t>(consumed) + 1;  // one whitespace byte after the scale
  std::size_t n = static_cast<std::size_t>(img.width) * img.height;  // both below 2^31: no overflow
  const std::size_t have = bytes->size() > start ? bytes->size() - start : 0;
  if (have / sizeof(float) < n)  // divided, not n * 4: a forged header must not wrap the product
    throw std::runtime_error(fmt::format("{}: error: truncated PFM ({} of {} pixel bytes)", util::display_path(path),
                                         have, n * sizeof(float)));
  img.pixels.resize(n);
  std::memcpy(img.pixels.data(), bytes->data() + start, n * sizeof(float));
  return img;
}

void write_png(const std::filesystem::path& path, const FloatImage& image) {
  bool special = false;
  for (float v : image.pixels) special |= !std::isfinite(v);
  int channels = special ? 3 : 1;
  std::vector<unsigned char> pixels(static_cast<std::size_t>(image.width) * image.height * channels);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float v = image.at(x, image.height - 1 - y);  // PNG is top row first
      unsigned char* p = &pixels[(static_cast<std::size_t>(y) * image.width + x) * channels];
      if (std::isnan(v)) { p[0] = 255; p[1] = 0; p[2] = 0; continue; }
      if (std::isinf(v)) { p[0] = 255; p[1] = 0; p[2] = 255; continue; }
      auto g = static_cast<unsigned char>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
      for (int c = 0; c < channels; ++c) p[c] = g;
    }
  std::string out;
  auto append = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &out, image.width, image.height, channels, pixels.data(),
                              image.width * channels))
    throw std::runtime_error(fmt::format("{}: error: PNG encoding failed", util::display_path(path)));
  util::write_atomic(path, out);
}

void write_rgb_png(const std::filesystem::path& path, int width, int height, const std::vector<unsigned char>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw std::invalid_argument(fmt::format("{}: error: {} RGB bytes for a {}x{} PNG (want {})",
                                            util::display_path(path), rgb.size(), width, height,
                                            static_cast<std::size_t>(std::max(width, 0)) * std::max(height, 0) * 3));
  std::string out;
  auto append = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &out, width, height, 3, rgb.data(), width * 3))
    throw std::runtime_error(fmt::format("{}: error: PNG encoding failed", util::display_path(path)));
  util::write_atomic(path, out);
}

}  // namespace aovar::image
