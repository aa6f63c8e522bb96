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
  return ViewScorer(truth, view, radius)(image);
}

ViewScorer::ViewScorer(const reference::ReferenceImage& truth, const scene::View& view, float radius)
    : truth_(&truth), prepared_(truth.visibility, truth.background) {
  const image::FloatImage& depth = truth.depth;
  has_depth_ = depth.width == truth.visibility.width && depth.height == truth.visibility.height && !depth.pixels.empty();
  if (!has_depth_) return;
  split_depth_ = metrics::median_depth(depth, truth.background);
  band_px_ = edge_band_px(view, radius, {depth.width, depth.height}, split_depth_);
}

metrics::ErrorStats ViewScorer::operator()(const image::FloatImage& image) const {
  metrics::ErrorStats s = metrics::compare(image, prepared_);
  if (has_depth_)
    s.breakdown = metrics::error_breakdown(image, truth_->visibility, truth_->background, truth_->depth, band_px_,
                                           split_depth_);
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
