// Where the error comes from (see breakdown.h): one pass over the compared pixels accumulates count, squared
// and signed error per part; the shares and RMSEs follow from those sums.
#include "metrics/breakdown.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "metrics/detail.h"

namespace aovar::metrics {
namespace {

using image::FloatImage;

constexpr double kNoData = std::numeric_limits<double>::quiet_NaN();

// Running sums of one part.
struct PartSums {
  long n = 0;
  double sq = 0, sum = 0;
  void add(double e) {
    ++n;
    sq += e * e;
    sum += e;
  }
};

ErrorPart part_of(const PartSums& p, long total_n, double total_sq) {
  if (total_n == 0) return {kNoData, kNoData, kNoData, kNoData};
  ErrorPart out;
  out.pixel_share = static_cast<double>(p.n) / static_cast<double>(total_n);
  out.rmse = p.n > 0 ? std::sqrt(p.sq / static_cast<double>(p.n)) : kNoData;
  out.mean_error = p.n > 0 ? p.sum / static_cast<double>(p.n) : kNoData;
  out.error_share = total_sq > 0 ? p.sq / total_sq : kNoData;
  return out;
}

// Distance in pixels from pixel (x, y)'s centre to the nearest screen edge.
double edge_distance(int x, int y, int w, int h) {
  return std::min({x, y, w - 1 - x, h - 1 - y}) + 0.5;
}

}  // namespace

double median_depth(const FloatImage& depth, const std::vector<std::uint8_t>& background) {
  detail::check_image(depth, "depth");
  detail::check_background(background, depth);
  std::vector<float> z;
  z.reserve(depth.pixels.size());
  for (std::size_t i = 0; i < depth.pixels.size(); ++i)
    if (detail::is_compared(background, i) && std::isfinite(depth.pixels[i])) z.push_back(depth.pixels[i]);
  if (z.empty()) return kNoData;
  // Nearest rank: index ceil(n / 2) - 1.
  const auto rank = static_cast<std::ptrdiff_t>((z.size() + 1) / 2 - 1);
  std::nth_element(z.begin(), z.begin() + rank, z.end());
  return z[static_cast<std::size_t>(rank)];
}

ErrorBreakdown error_breakdown(const FloatImage& image, const FloatImage& reference,
                               const std::vector<std::uint8_t>& background, const FloatImage& depth,
                               double edge_band_px) {
  detail::check_pair(image, "image", reference, "reference");
  detail::check_pair(depth, "depth", image, "image");
  detail::check_background(background, image);  // before median_depth, as the split's own checks
  return error_breakdown(image, reference, background, depth, edge_band_px, median_depth(depth, background));
}

ErrorBreakdown error_breakdown(const FloatImage& image, const FloatImage& reference,
                               const std::vector<std::uint8_t>& background, const FloatImage& depth,
                               double edge_band_px, double split_depth) {
  detail::check_pair(image, "image", reference, "reference");
  detail::check_pair(depth, "depth", image, "image");
  detail::check_background(background, image);
  if (!(edge_band_px >= 0) || !std::isfinite(edge_band_px))
    throw std::invalid_argument(fmt::format("metrics: edge band {} px must be finite and >= 0", edge_band_px));

  ErrorBreakdown b;
  b.edge_band_px = edge_band_px;
  b.split_depth = split_depth;
  PartSums edge, interior, near, far, light, dark;
  long n = 0;
  double total_sq = 0;
  const int w = image.width, h = image.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      const float v = image.pixels[i], r = reference.pixels[i];
      if (!detail::is_compared(background, i) || !std::isfinite(v) || !std::isfinite(r)) continue;
      const double e = static_cast<double>(v) - static_cast<double>(r);
      ++n;
      total_sq += e * e;
      (edge_distance(x, y, w, h) < edge_band_px ? edge : interior).add(e);
      if (const float z = depth.pixels[i]; std::isfinite(z)) (z <= b.split_depth ? near : far).add(e);
      if (e > 0) light.add(e);
      if (e < 0) dark.add(e);
    }
  b.edge = part_of(edge, n, total_sq);
  b.interior = part_of(interior, n, total_sq);
  b.near = part_of(near, n, total_sq);
  b.far = part_of(far, n, total_sq);
  b.light = part_of(light, n, total_sq);
  b.dark = part_of(dark, n, total_sq);
  return b;
}

}  // namespace aovar::metrics
