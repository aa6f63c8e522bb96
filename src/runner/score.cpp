// Scoring against the reference (see score.h).
#include "runner/score.h"

#include <algorithm>
#include <cmath>

namespace aovar::runner {

metrics::ErrorStats score(const image::FloatImage& image, const reference::ReferenceImage& truth) {
  return metrics::compare(image, truth.visibility, truth.background);
}

metrics::ErrorStats score(const image::FloatImage& image, const reference::ReferenceImage& truth,
                          const scene::View& view, float radius) {
  metrics::ErrorStats s = score(image, truth);
  const image::FloatImage& depth = truth.depth;
  if (depth.width != image.width || depth.height != image.height || depth.pixels.empty()) return s;
  const double band = edge_band_px(view, radius, {image.width, image.height}, metrics::median_depth(depth, truth.background));
  s.breakdown = metrics::error_breakdown(image, truth.visibility, truth.background, depth, band);
  return s;
}

double edge_band_px(const scene::View& view, float radius, render::Extent size, double median_depth) {
  if (!(median_depth > 0) || !std::isfinite(median_depth)) return 0;
  render::FrameSetup setup;
  setup.view = &view;
  setup.static_camera = true;
  setup.radius = radius;
  const render::FrameBlock b = render::make_frame_block(setup, size, size, render::ClipDepth::zero_to_one);
  const double reach = static_cast<double>(b.clip.z) * b.clip.w / median_depth;
  return std::min(reach, 0.25 * std::min(size.width, size.height));
}

}  // namespace aovar::runner
