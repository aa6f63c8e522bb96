#include "image/health.h"

#include <stdexcept>
#include <string>

namespace aovar::image {

Health health(const FloatImage& image, const std::vector<std::uint8_t>& skip) {
  if (!skip.empty() && skip.size() != image.pixels.size())
    throw std::invalid_argument("image::health: mask has " + std::to_string(skip.size()) + " entries for " +
                                std::to_string(image.pixels.size()) + " pixels");
  Health h;
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    if (skip.empty() || !skip[i]) count(h, image.pixels[i]);
  return h;
}

}  // namespace aovar::image
