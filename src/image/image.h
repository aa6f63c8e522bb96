#pragma once
// Single-channel float images (AO results, references, error maps) and their files: PFM keeps every
// float bit-exact (NaN and Inf included), PNG is an 8-bit preview for people.
#include <filesystem>
#include <string>
#include <vector>

namespace aovar::image {

struct FloatImage {
  int width = 0, height = 0;
  std::vector<float> pixels;  // row-major, row 0 = bottom (OpenGL and PFM order)

  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  float& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

// Little-endian greyscale PFM ("Pf"), written atomically. Throws std::runtime_error naming the path.
void write_pfm(const std::filesystem::path& path, const FloatImage& image);
FloatImage read_pfm(const std::filesystem::path& path);

// 8-bit greyscale PNG, top row first, values clamped to [0, 1]; NaN is drawn red and Inf magenta (RGB PNG
// then) so they stand out. Written atomically.
void write_png(const std::filesystem::path& path, const FloatImage& image);

// 8-bit RGB PNG from `rgb` (width * height * 3 bytes, top row first), written atomically. Throws
// std::invalid_argument when the byte count does not match the size, std::runtime_error naming the path.
void write_rgb_png(const std::filesystem::path& path, int width, int height, const std::vector<unsigned char>& rgb);

}  // namespace aovar::image
