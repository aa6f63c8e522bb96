#pragma once
// SSIM's window sums (Wang et al. 2004: 11x11 Gaussian, sigma 1.5, C1 = 0.01^2, C2 = 0.03^2) with masked
// windows, split so that what depends on the reference alone is computed once per reference
// (metrics::PreparedReference) and only the image's own channels per compared image.
//
// A window sum is separable: one horizontal and one vertical 11-tap pass. Each channel is summed on its own,
// tap by tap over whole rows, and an invalid pixel adds 0 instead of being skipped. Each pixel still adds its
// taps in the order of the direct loop (left to right, then top to bottom), and no partial sum is ever -0
// (they start at +0), so adding 0 changes no bit: the result does not depend on how the loops are arranged.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace aovar::metrics::detail {

// The reference's channels over one mask of valid pixels: the vertical window sums of the weight (w), of the
// value (y) and of its square (yy), and the masked values themselves (0 where invalid).
struct ReferenceMoments {
  std::vector<std::uint8_t> valid;
  std::vector<double> masked;  // the reference's value where valid, else 0
  std::vector<double> w, y, yy;
};

ReferenceMoments reference_moments(const image::FloatImage& reference, std::vector<std::uint8_t> valid);

// The sum of the SSIM map over the valid pixels of `reference.valid` (the caller divides by their count):
// `image` is read only where valid.
double ssim_sum(const image::FloatImage& image, const ReferenceMoments& reference);

}  // namespace aovar::metrics::detail
