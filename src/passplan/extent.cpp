#include "passplan/extent.h"

#include <algorithm>
#include <cmath>

namespace aovar::passplan {

Extent ao_extent(Extent full, double resolution) {
  auto scale = [&](int n) { return std::max(1, static_cast<int>(std::ceil(n * resolution - 1e-9))); };
  return {scale(full.width), scale(full.height)};
}

int mip_levels_at(Extent e) {
  int possible = 1;
  while ((std::max(e.width, e.height) >> possible) > 0) ++possible;
  return possible;
}

}  // namespace aovar::passplan
