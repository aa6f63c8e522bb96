#pragma once
// Internals shared by the files of src/metrics: the size and mask checks every comparison starts with.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace aovar::metrics::detail {

std::size_t pixel_count(const image::FloatImage& img);
// std::invalid_argument naming what is wrong: a size that does not match, pixels that do not fill the size,
// a non-empty mask without one entry per pixel.
void check_image(const image::FloatImage& img, const char* what);
void check_pair(const image::FloatImage& a, const char* what_a, const image::FloatImage& b, const char* what_b);
void check_background(const std::vector<std::uint8_t>& background, const image::FloatImage& img);
// The mask's convention: empty compares every pixel, 1 skips one.
bool is_compared(const std::vector<std::uint8_t>& background, std::size_t i);

}  // namespace aovar::metrics::detail
