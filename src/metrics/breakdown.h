#pragma once
// Where an image's error against its reference comes from (docs/cli.md, "File formats"): the squared error split
// three ways, so that a reader sees why a method loses, not only that it does —
//  - screen-edge band vs interior: taps leave the frame near the screen edges, so a method that is only
//    wrong there is wrong about the frame, not about the scene;
//  - near vs far half, split at the median linear depth: a screen-space method sees one depth layer, and
//    the far half (small on screen) is where the radius covers few pixels;
//  - too light vs too dark: lighter than the reference is missed occlusion (occluders hidden behind the
//    visible layer or outside the frame), darker is over-occlusion (haloes, self-occlusion).
// Computed over the same pixels as metrics::compare: not background, image and reference both finite.
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace aovar::metrics {

// One part of the compared pixels. Every figure is NaN when no pixel entered the comparison; rmse and
// mean_error are NaN for a part with no pixel; error_share is NaN when the total squared error is 0
// (nothing to attribute).
struct ErrorPart {
  double pixel_share = 0;  // the part's pixels / the compared finite pixels
  double rmse = 0;         // over the part's pixels
  double error_share = 0;  // the part's squared error / the total squared error
  double mean_error = 0;   // mean of image - reference over the part's pixels (> 0: lighter)
  bool operator==(const ErrorPart&) const = default;
};

struct ErrorBreakdown {
  double edge_band_px = 0;  // a pixel whose centre lies closer than this to a screen edge is in `edge`
  double split_depth = 0;   // median linear depth (median_depth): `near` <= split_depth < `far`
  ErrorPart edge, interior;
  ErrorPart near, far;      // a compared pixel without a finite depth is in neither
  ErrorPart light, dark;    // image > reference, image < reference; an exact pixel is in neither
  bool operator==(const ErrorBreakdown&) const = default;
};

// The lower median (nearest rank: the smallest value with at least half the values <= it) of the finite
// depths of the pixels the mask compares (`background` as compare's: 1 = skip; empty = every pixel).
// NaN when there is none. std::invalid_argument for a mask of the wrong size.
double median_depth(const image::FloatImage& depth, const std::vector<std::uint8_t>& background = {});

// `depth`: linear view depth per pixel (row 0 = bottom, as the images; +inf on background), the same size
// as the images. `edge_band_px` >= 0 (0: no band, every pixel is interior). The near/far split is
// median_depth(depth, background), so it is the same for every image scored against one reference.
// std::invalid_argument for mismatched sizes or a band that is negative or not finite.
ErrorBreakdown error_breakdown(const image::FloatImage& image, const image::FloatImage& reference,
                               const std::vector<std::uint8_t>& background, const image::FloatImage& depth,
                               double edge_band_px);

// The same with the near/far split given: median_depth(depth, background), computed once for the many images
// scored against one reference.
ErrorBreakdown error_breakdown(const image::FloatImage& image, const image::FloatImage& reference,
                               const std::vector<std::uint8_t>& background, const image::FloatImage& depth,
                               double edge_band_px, double split_depth);

}  // namespace aovar::metrics
