#pragma once
// The one NaN / Inf / out-of-[0, 1] counter: every AO result, reference comparison, stress check and
// cost-table row reports its health with this type.
#include <cmath>
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace aovar::image {

struct Health {
  long nan = 0, inf = 0, out_of_range = 0;
  long pixels = 0;  // the pixels counted (every pixel, or those the mask leaves in)
  long bad() const { return nan + inf + out_of_range; }
  bool operator==(const Health&) const = default;
};

// Counts NaN, Inf and finite values outside [0, 1]. `skip` (may be empty): 1 = leave the pixel out; it must
// then hold one entry per pixel (std::invalid_argument otherwise).
Health health(const FloatImage& image, const std::vector<std::uint8_t>& skip = {});

// Adds one value to the counts (for callers that walk pixels themselves).
inline void count(Health& h, float v) {
  ++h.pixels;
  if (std::isnan(v)) ++h.nan;
  else if (std::isinf(v)) ++h.inf;
  else if (v < 0.0f || v > 1.0f) ++h.out_of_range;
}

}  // namespace aovar::image
