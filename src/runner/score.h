#pragma once
// Scoring a rendered image against a view's ray-traced reference (docs/architecture.md, "Ground truth and
// error"): the error statistics, and for a row where the error comes from (metrics/breakdown.h).
#include "image/image.h"
#include "metrics/metrics.h"
#include "reference/reference.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace aovar::runner {

// The error of an image against a view's ray-traced reference, over the reference's geometry pixels.
metrics::ErrorStats score(const image::FloatImage& image, const reference::ReferenceImage& truth);

// The same, with `breakdown` set (metrics::error_breakdown over the reference's depth, the band of
// edge_band_px) when the reference has a depth of the image's size; without one (a reference loaded from
// files, which hold none), as score() above.
metrics::ErrorStats score(const image::FloatImage& image, const reference::ReferenceImage& truth,
                          const scene::View& view, float radius);

// Scores the many images of one view against its reference: what depends on the reference alone (compare's
// metrics::PreparedReference, the median depth and the edge band) is computed once. Bit for bit the score above.
// It refers to `truth`, which must outlive it.
class ViewScorer {
 public:
  ViewScorer(const reference::ReferenceImage& truth, const scene::View& view, float radius);
  metrics::ErrorStats operator()(const image::FloatImage& image) const;

 private:
  const reference::ReferenceImage* truth_;
  metrics::PreparedReference prepared_;
  bool has_depth_ = false;  // a depth of the reference's size: the breakdown is known
  double split_depth_ = 0, band_px_ = 0;
};

// The screen-edge band: the AO radius in pixels at `median_depth` (the shaders' ao_radius_px, from the frame
// block they get: clip.z * clip.w / z), capped like it at a quarter of the shorter side. A tap reaches at
// most that far from its pixel, so a pixel closer than this to an edge has taps that leave the frame; the
// view's median depth gives one band per view, the same for every variant scored against it. 0 when the
// median is not a positive number (no geometry).
double edge_band_px(const scene::View& view, float radius, render::Extent size, double median_depth);

}  // namespace aovar::runner
