// Error statistics of an AO image against its reference (docs/architecture.md, "Ground truth and error"). Every average runs over the
// compared pixels (not background) where both images are finite; the image's NaN, Inf and out-of-[0, 1]
// values are counted in Health instead. SSIM follows Wang et al. 2004 (11x11 Gaussian, sigma 1.5,
// C1 = 0.01^2, C2 = 0.03^2) with masked windows: each window's weights are renormalised over the pixels
// that enter it, so image borders, background and non-finite pixels change nothing but the weights. The
// window sums are in ssim.cpp; the reference's share of them is computed once per PreparedReference.
#include "metrics/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "metrics/detail.h"
#include "metrics/ssim.h"

namespace aovar::metrics {

using image::FloatImage;

namespace detail {

std::size_t pixel_count(const FloatImage& img) {
  return static_cast<std::size_t>(std::max(img.width, 0)) * static_cast<std::size_t>(std::max(img.height, 0));
}

void check_image(const FloatImage& img, const char* what) {
  if (img.width < 0 || img.height < 0 || img.pixels.size() != pixel_count(img))
    throw std::invalid_argument(fmt::format("metrics: {} is {}x{} but holds {} pixels", what, img.width,
                                            img.height, img.pixels.size()));
}

void check_pair(const FloatImage& a, const char* what_a, const FloatImage& b, const char* what_b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument(fmt::format("metrics: {} is {}x{} but {} is {}x{}", what_a, a.width, a.height,
                                            what_b, b.width, b.height));
  check_image(a, what_a);
  check_image(b, what_b);
}

void check_background(const std::vector<std::uint8_t>& background, const FloatImage& img) {
  if (!background.empty() && background.size() != pixel_count(img))
    throw std::invalid_argument(fmt::format("metrics: background mask has {} entries for a {}x{} image ({})",
                                            background.size(), img.width, img.height, pixel_count(img)));
}

bool is_compared(const std::vector<std::uint8_t>& background, std::size_t i) {
  return background.empty() || background[i] == 0;
}

}  // namespace detail

namespace {

using detail::check_background;
using detail::check_pair;
using detail::is_compared;
using detail::pixel_count;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

PreparedReference::PreparedReference(const FloatImage& reference, const std::vector<std::uint8_t>& background)
    : reference_(&reference), background_(&background) {
  detail::check_image(reference, "reference");
  check_background(background, reference);
  std::vector<std::uint8_t> valid(pixel_count(reference), 0);
  for (std::size_t i = 0; i < valid.size(); ++i)
    valid[i] = is_compared(background, i) && std::isfinite(reference.pixels[i]);
  moments_ = std::make_shared<const detail::ReferenceMoments>(detail::reference_moments(reference, std::move(valid)));
}

ErrorStats compare(const FloatImage& image, const FloatImage& reference, const std::vector<std::uint8_t>& background) {
  check_pair(image, "image", reference, "reference");
  return compare(image, PreparedReference(reference, background));
}

ErrorStats compare(const FloatImage& image, const PreparedReference& prepared) {
  const FloatImage& reference = prepared.reference();
  const std::vector<std::uint8_t>& background = prepared.background();
  check_pair(image, "image", reference, "reference");
  const std::size_t n = pixel_count(image);

  ErrorStats s;
  bool finite_where_reference_is = true;  // else the windows are the reference's over fewer pixels
  double sum = 0, sum_abs = 0, sum_sq = 0, max_abs = 0;
  long over = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_compared(background, i)) continue;
    const float v = image.pixels[i], r = reference.pixels[i];
    image::count(s.health, v);
    if (!std::isfinite(r)) continue;
    if (!std::isfinite(v)) {
      finite_where_reference_is = false;
      continue;
    }
    ++s.finite;
    const double e = static_cast<double>(v) - static_cast<double>(r), ae = std::abs(e);
    sum += e;
    sum_abs += ae;
    sum_sq += e * e;
    max_abs = std::max(max_abs, ae);
    over += ae > 0.1;
  }

  if (s.finite == 0) {  // nothing to average: no number would be honest
    s.rmse = s.mae = s.psnr = s.ssim = s.bias = s.max = s.share_over_0_1 = kNaN;
    return s;
  }
  const double count = static_cast<double>(s.finite);
  const double mse = sum_sq / count;
  s.rmse = std::sqrt(mse);
  s.mae = sum_abs / count;
  s.bias = sum / count;
  s.max = max_abs;
  s.psnr = mse == 0 ? std::numeric_limits<double>::infinity() : -10.0 * std::log10(mse);  // peak 1
  s.share_over_0_1 = static_cast<double>(over) / count;
  if (finite_where_reference_is) {
    s.ssim = detail::ssim_sum(image, *prepared.moments_) / count;
  } else {
    std::vector<std::uint8_t> valid = prepared.moments_->valid;
    for (std::size_t i = 0; i < n; ++i) valid[i] = valid[i] && std::isfinite(image.pixels[i]);
    s.ssim = detail::ssim_sum(image, detail::reference_moments(reference, std::move(valid))) / count;
  }
  return s;
}

void write_error_heatmap(const std::filesystem::path& path, const FloatImage& image, const FloatImage& reference,
                         const std::vector<std::uint8_t>& background, double scale) {
  check_pair(image, "image", reference, "reference");
  check_background(background, image);
  if (!(scale > 0) || !std::isfinite(scale))
    throw std::invalid_argument(fmt::format("metrics: heat map scale must be finite and > 0 (got {})", scale));
  const int w = image.width, h = image.height;
  std::vector<unsigned char> rgb(pixel_count(image) * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      unsigned char* p = &rgb[(static_cast<std::size_t>(h - 1 - y) * w + x) * 3];  // PNG: top row first
      if (!is_compared(background, i)) {
        p[0] = p[1] = p[2] = 128;
        continue;
      }
      const float v = image.pixels[i], r = reference.pixels[i];
      if (!std::isfinite(v) || !std::isfinite(r)) {
        p[0] = p[1] = p[2] = 0;
        continue;
      }
      const double e = static_cast<double>(v) - static_cast<double>(r);
      const double t = std::min(std::abs(e) / scale, 1.0);
      const auto fade = static_cast<unsigned char>(std::lround(255.0 * (1.0 - t)));
      if (e < 0) {  // darker than the reference: red
        p[0] = 255;
        p[1] = p[2] = fade;
      } else {  // lighter: blue (white at 0)
        p[0] = p[1] = fade;
        p[2] = 255;
      }
    }
  image::write_rgb_png(path, w, h, rgb);
}

double flicker(const std::vector<FloatImage>& frames, const std::vector<std::uint8_t>& background) {
  if (frames.size() < 2)
    throw std::invalid_argument(fmt::format("metrics: flicker needs at least 2 frames (got {})", frames.size()));
  for (std::size_t f = 1; f < frames.size(); ++f) check_pair(frames[f], "frame", frames[0], "first frame");
  check_background(background, frames[0]);
  const std::size_t n = pixel_count(frames[0]);
  double sum = 0;
  long count = 0;
  for (std::size_t f = 1; f < frames.size(); ++f)
    for (std::size_t i = 0; i < n; ++i) {
      if (!is_compared(background, i)) continue;
      const float a = frames[f].pixels[i], b = frames[f - 1].pixels[i];
      if (!std::isfinite(a) || !std::isfinite(b)) continue;
      sum += std::abs(static_cast<double>(a) - static_cast<double>(b));
      ++count;
    }
  return count == 0 ? kNaN : sum / static_cast<double>(count);
}

FloatImage average(const FloatImage& a, const FloatImage& b) {
  check_pair(a, "first image", b, "second image");
  FloatImage out;
  out.width = a.width;
  out.height = a.height;
  out.pixels.resize(a.pixels.size());
  for (std::size_t i = 0; i < a.pixels.size(); ++i)
    out.pixels[i] = static_cast<float>(0.5 * (static_cast<double>(a.pixels[i]) + static_cast<double>(b.pixels[i])));
  return out;
}

}  // namespace aovar::metrics
