#pragma once
// Error of an AO image against a reference over the non-background pixels (docs/architecture.md, "Ground truth and error"): RMSE, MAE,
// PSNR (peak 1), SSIM, mean bias, max error, share of pixels off by more than 0.1, and the NaN, Inf and
// out-of-[0, 1] counts. Non-finite pixels are counted, never averaged in.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "image/health.h"
#include "image/image.h"
#include "metrics/breakdown.h"

namespace aovar::metrics {

namespace detail {
struct ReferenceMoments;
}

struct ErrorStats {
  double rmse = 0, mae = 0, psnr = 0, ssim = 1, bias = 0, max = 0;
  double share_over_0_1 = 0;  // fraction of finite compared pixels with |error| > 0.1
  image::Health health;  // of the compared (non-background) pixels
  long finite = 0;            // compared pixels that entered the averages
  // Where the error comes from (metrics/breakdown.h): set where the depth is known (runner::score with a
  // view), not by compare(); nullopt in rows written before it.
  std::optional<ErrorBreakdown> breakdown;
  bool operator==(const ErrorStats&) const = default;
};

// `background`: 1 = skip the pixel (may be empty: compare every pixel). Images must have the same size
// and a non-empty mask one entry per pixel (std::invalid_argument naming the sizes otherwise).
// Health counts the image's values over the compared pixels; the averages run over the compared pixels
// where image and reference are both finite (`finite`; a non-finite reference pixel is left out, not
// counted). bias = mean(image - reference). PSNR is +inf for identical images. With no such pixel
// (finite == 0) every average, PSNR and SSIM are NaN.
// SSIM: 11x11 Gaussian window (sigma 1.5), C1 = 0.01^2, C2 = 0.03^2, a window at every compared pixel,
// reaching across the whole image; only compared finite pixels enter a window (background and non-finite
// pixels of either image are left out, and at image borders the window is cut): its Gaussian weights are
// renormalised over the pixels that enter it. The SSIM map is averaged over the compared finite pixels.
// So nothing under the mask, nor a NaN or Inf, changes any metric but the counts.
ErrorStats compare(const image::FloatImage& image, const image::FloatImage& reference,
                   const std::vector<std::uint8_t>& background = {});

// compare()'s work that depends on the reference alone (its valid pixels and SSIM window sums), done once for
// the many images compared against one reference. It refers to `reference` and `background`, which must
// outlive it. std::invalid_argument as compare's for pixels that do not fill the size or a mask of the wrong
// size.
class PreparedReference {
 public:
  PreparedReference(const image::FloatImage& reference, const std::vector<std::uint8_t>& background = {});
  const image::FloatImage& reference() const { return *reference_; }
  const std::vector<std::uint8_t>& background() const { return *background_; }

 private:
  friend ErrorStats compare(const image::FloatImage& image, const PreparedReference& reference);
  const image::FloatImage* reference_;
  const std::vector<std::uint8_t>* background_;
  std::shared_ptr<const detail::ReferenceMoments> moments_;
};

// The same as compare(image, reference.reference(), reference.background()), bit for bit: an image that is not
// finite where the reference is has its windows summed again over its own valid pixels.
ErrorStats compare(const image::FloatImage& image, const PreparedReference& reference);

// Signed error heat map as an RGB PNG: white at 0, red where the image is darker (more occluded) than the
// reference, blue where lighter, saturating at |error| = `scale`; background mid-grey (128); NaN/Inf (of
// either image) black. Top row first, written atomically. Exactly: error e = image - reference,
// f = round(255 * (1 - min(|e| / scale, 1))); e < 0 -> (255, f, f), e >= 0 -> (f, f, 255).
// std::invalid_argument for mismatched sizes or a scale that is not finite and > 0.
void write_error_heatmap(const std::filesystem::path& path, const image::FloatImage& image,
                         const image::FloatImage& reference, const std::vector<std::uint8_t>& background = {},
                         double scale = 0.25);

// Progressive variants (docs/architecture.md, "Ground truth and error"): the error of one frame, of the average of two consecutive frames
// (the two halves on a static camera), and flicker = mean |AO_t - AO_{t-1}| over compared finite pixels
// along a sequence of frames (a camera path): the differences of all consecutive pairs pooled into one
// mean. std::invalid_argument for fewer than 2 frames or mismatched sizes; NaN when no pixel pair is
// compared and finite. average() is the per-pixel mean (a NaN or Inf stays); sizes must match.
double flicker(const std::vector<image::FloatImage>& frames, const std::vector<std::uint8_t>& background = {});
image::FloatImage average(const image::FloatImage& a, const image::FloatImage& b);

}  // namespace aovar::metrics
