// Error statistics of an AO image against its reference (docs/architecture.md, "Ground truth and error"). Every average runs over the
// compared pixels (not background) where both images are finite; the image's NaN, Inf and out-of-[0, 1]
// values are counted in Health instead. SSIM follows Wang et al. 2004 (11x11 Gaussian, sigma 1.5,
// C1 = 0.01^2, C2 = 0.03^2) with masked windows: each window's weights are renormalised over the pixels
// that enter it, so image borders, background and non-finite pixels change nothing but the weights. The
// window sums are separable: one horizontal and one vertical 11-tap pass over six moment channels.
#include "metrics/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "metrics/detail.h"

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

constexpr int kRadius = 5;  // 11 taps
constexpr double kSigma = 1.5;
constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Normalised 1-D Gaussian taps, index 0 = offset -kRadius.
std::array<double, 2 * kRadius + 1> gaussian_taps() {
  std::array<double, 2 * kRadius + 1> taps{};
  double sum = 0;
  for (int k = -kRadius; k <= kRadius; ++k) sum += taps[k + kRadius] = std::exp(-(k * k) / (2 * kSigma * kSigma));
  for (double& t : taps) t /= sum;
  return taps;
}

// Weighted window moments: sum of weights, of x, y, x^2, y^2, x*y.
struct Moments {
  double w = 0, x = 0, y = 0, xx = 0, yy = 0, xy = 0;
  void add(double g, const Moments& m) {
    w += g * m.w;
    x += g * m.x;
    y += g * m.y;
    xx += g * m.xx;
    yy += g * m.yy;
    xy += g * m.xy;
  }
};

// Mean SSIM over the pixels with valid[i] != 0; only those pixels enter the windows. Returns the sum of
// the SSIM map (the caller divides by the number of valid pixels).
double ssim_sum(const FloatImage& a, const FloatImage& b, const std::vector<std::uint8_t>& valid) {
  const int w = a.width, h = a.height;
  const auto taps = gaussian_taps();
  const std::size_t n = pixel_count(a);

  // Horizontal pass straight from the pixels (an invalid pixel contributes nothing).
  std::vector<Moments> horiz(n);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      Moments acc;
      const int lo = std::max(x - kRadius, 0), hi = std::min(x + kRadius, w - 1);
      for (int xx = lo; xx <= hi; ++xx) {
        const std::size_t j = row + xx;
        if (!valid[j]) continue;
        const double g = taps[xx - x + kRadius];
        const double va = a.pixels[j], vb = b.pixels[j];
        acc.w += g;
        acc.x += g * va;
        acc.y += g * vb;
        acc.xx += g * va * va;
        acc.yy += g * vb * vb;
        acc.xy += g * va * vb;
      }
      horiz[row + x] = acc;
    }
  }

  // Vertical pass, evaluated only where the map is averaged. A whole output row is accumulated one input row
  // at a time (reading rows in memory order); each pixel still adds its rows in the order yy = lo..hi.
  double sum = 0;
  std::vector<Moments> column(static_cast<std::size_t>(w));
  for (int y = 0; y < h; ++y) {
    const int lo = std::max(y - kRadius, 0), hi = std::min(y + kRadius, h - 1);
    const std::size_t row = static_cast<std::size_t>(y) * w;
    std::fill(column.begin(), column.end(), Moments{});
    for (int yy = lo; yy <= hi; ++yy) {
      const double g = taps[yy - y + kRadius];
      const Moments* in = &horiz[static_cast<std::size_t>(yy) * w];
      for (int x = 0; x < w; ++x)
        if (valid[row + x]) column[x].add(g, in[x]);
    }
    for (int x = 0; x < w; ++x) {
      if (!valid[row + x]) continue;
      const Moments& m = column[x];
      // m.w > 0: the centre pixel itself is valid.
      const double mx = m.x / m.w, my = m.y / m.w;
      const double vx = std::max(m.xx / m.w - mx * mx, 0.0);
      const double vy = std::max(m.yy / m.w - my * my, 0.0);
      const double cxy = m.xy / m.w - mx * my;
      sum += ((2 * mx * my + kC1) * (2 * cxy + kC2)) / ((mx * mx + my * my + kC1) * (vx + vy + kC2));
    }
  }
  return sum;
}

}  // namespace

ErrorStats compare(const FloatImage& image, const FloatImage& reference, const std::vector<std::uint8_t>& background) {
  check_pair(image, "image", reference, "reference");
  check_background(background, image);
  const std::size_t n = pixel_count(image);

  ErrorStats s;
  std::vector<std::uint8_t> valid(n, 0);
  double sum = 0, sum_abs = 0, sum_sq = 0, max_abs = 0;
  long over = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_compared(background, i)) continue;
    const float v = image.pixels[i], r = reference.pixels[i];
    image::count(s.health, v);
    if (!std::isfinite(v) || !std::isfinite(r)) continue;
    valid[i] = 1;
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
  s.ssim = ssim_sum(image, reference, valid) / count;
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
