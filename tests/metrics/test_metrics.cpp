// Error metrics against a reference: exact values on constructed cases, SSIM against a direct 11x11 window
// sum, background and non-finite pixels left out of every average, the heat map's colours, flicker and the
// two-frame average.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#define STB_IMAGE_STATIC  // file-local: no clash with another copy of stb_image linked in
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "image/image.h"
#include "metrics/metrics.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

using image::FloatImage;


// Smooth shading plus hard edges, well inside (0, 1), values on a 1/256 grid (exact offsets stay exact).
FloatImage structured(int w, int h) {
  FloatImage img = filled_image(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = 0.5 + 0.2 * std::sin(0.35 * x) * std::cos(0.22 * y) + ((x / 8 + y / 8) % 2 ? 0.1 : -0.1);
      img.at(x, y) = static_cast<float>(std::round(v * 256.0) / 256.0);
    }
  return img;
}

FloatImage with_noise(const FloatImage& src, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  FloatImage out = src;
  for (float& v : out.pixels) v = static_cast<float>(std::clamp(v + noise(rng), 0.0, 1.0));
  return out;
}

FloatImage box_blur(const FloatImage& src, int radius) {
  FloatImage out = src;
  for (int y = 0; y < src.height; ++y)
    for (int x = 0; x < src.width; ++x) {
      double sum = 0;
      int n = 0;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= src.width || yy >= src.height) continue;
          sum += src.at(xx, yy);
          ++n;
        }
      out.at(x, y) = static_cast<float>(sum / n);
    }
  return out;
}

// SSIM straight from the definition: at every compared finite pixel, the full 11x11 window (121 taps) of
// compared finite pixels, Gaussian weights renormalised over them, two-pass means and (co)variances.
double direct_ssim(const FloatImage& a, const FloatImage& b, const std::vector<std::uint8_t>& background) {
  auto valid = [&](int x, int y) {
    std::size_t i = static_cast<std::size_t>(y) * a.width + x;
    return (background.empty() || background[i] == 0) && std::isfinite(a.pixels[i]) && std::isfinite(b.pixels[i]);
  };
  // tap(xx, yy, g) for each compared finite pixel of the 11x11 window at (x, y), with its Gaussian weight: both
  // passes visit the same taps in the same order.
  auto each_tap = [&](int x, int y, auto&& tap) {
    for (int dy = -5; dy <= 5; ++dy)
      for (int dx = -5; dx <= 5; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= a.width || yy >= a.height || !valid(xx, yy)) continue;
        tap(xx, yy, std::exp(-(dx * dx + dy * dy) / (2 * 1.5 * 1.5)));
      }
  };
  double total = 0;
  long count = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (!valid(x, y)) continue;
      double wsum = 0, mx = 0, my = 0;
      each_tap(x, y, [&](int xx, int yy, double g) {
        wsum += g;
        mx += g * a.at(xx, yy);
        my += g * b.at(xx, yy);
      });
      mx /= wsum;
      my /= wsum;
      double vx = 0, vy = 0, cxy = 0;
      each_tap(x, y, [&](int xx, int yy, double g) {
        const double da = a.at(xx, yy) - mx, db = b.at(xx, yy) - my;
        vx += g * da * da;
        vy += g * db * db;
        cxy += g * da * db;
      });
      vx /= wsum;
      vy /= wsum;
      cxy /= wsum;
      const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
      total += ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++count;
    }
  return total / count;
}

void expect_same_stats(const metrics::ErrorStats& a, const metrics::ErrorStats& b) {
  EXPECT_DOUBLE_EQ(a.rmse, b.rmse);
  EXPECT_DOUBLE_EQ(a.mae, b.mae);
  EXPECT_DOUBLE_EQ(a.psnr, b.psnr);
  EXPECT_NEAR(a.ssim, b.ssim, 1e-12);
  EXPECT_DOUBLE_EQ(a.bias, b.bias);
  EXPECT_DOUBLE_EQ(a.max, b.max);
  EXPECT_DOUBLE_EQ(a.share_over_0_1, b.share_over_0_1);
  EXPECT_EQ(a.finite, b.finite);
}

TEST(Metrics, IdenticalImagesArePerfect) {
  auto ref = structured(40, 30);
  auto s = metrics::compare(ref, ref);
  EXPECT_EQ(s.rmse, 0.0);
  EXPECT_EQ(s.mae, 0.0);
  EXPECT_EQ(s.bias, 0.0);
  EXPECT_EQ(s.max, 0.0);
  EXPECT_EQ(s.share_over_0_1, 0.0);
  EXPECT_NEAR(s.ssim, 1.0, 1e-12);
  EXPECT_TRUE(std::isinf(s.psnr) && s.psnr > 0);
  EXPECT_EQ(s.finite, 40 * 30);
  EXPECT_EQ(s.health.pixels, 40 * 30);
  EXPECT_EQ(s.health.nan + s.health.inf + s.health.out_of_range, 0);
}

TEST(Metrics, ConstantOffsetGivesExactErrors) {
  auto ref = structured(40, 30);  // values in [0.2, 0.8]: an offset of up to 0.125 stays inside [0, 1]
  for (double c : {0.0625, -0.0625, 0.125, -0.125}) {
    SCOPED_TRACE(c);
    auto img = ref;
    for (float& v : img.pixels) v = static_cast<float>(v + c);  // exact: both on a 1/256 grid
    auto s = metrics::compare(img, ref);
    EXPECT_DOUBLE_EQ(s.bias, c);
    EXPECT_DOUBLE_EQ(s.rmse, std::abs(c));
    EXPECT_DOUBLE_EQ(s.mae, std::abs(c));
    EXPECT_DOUBLE_EQ(s.max, std::abs(c));
    EXPECT_NEAR(s.psnr, -20.0 * std::log10(std::abs(c)), 1e-12);
    EXPECT_EQ(s.share_over_0_1, std::abs(c) > 0.1 ? 1.0 : 0.0);
    EXPECT_LT(s.ssim, 1.0);  // luminance term only: structure is intact
    EXPECT_GT(s.ssim, 0.8);
    EXPECT_EQ(s.health.out_of_range, 0);
  }
}

TEST(Metrics, SsimFallsWithNoiseAndBlur) {
  auto ref = structured(64, 48);
  double previous = metrics::compare(ref, ref).ssim;
  for (double sigma : {0.01, 0.03, 0.1, 0.3}) {
    SCOPED_TRACE(sigma);
    double ssim = metrics::compare(with_noise(ref, sigma, 7), ref).ssim;
    EXPECT_LT(ssim, previous);
    EXPECT_GT(ssim, -1.0);
    previous = ssim;
  }
  double blur1 = metrics::compare(box_blur(ref, 1), ref).ssim;
  double blur3 = metrics::compare(box_blur(ref, 3), ref).ssim;
  EXPECT_LT(blur1, 1.0);
  EXPECT_LT(blur3, blur1);
  // SSIM is symmetric in its two images.
  auto noisy = with_noise(ref, 0.05, 3);
  EXPECT_NEAR(metrics::compare(noisy, ref).ssim, metrics::compare(ref, noisy).ssim, 1e-12);
}

// One reference prepared, many images compared against it, interleaved with another reference of another size
// (the comparisons' scratch buffers are reused): each SSIM is the direct window sum's, and the same image gives
// the same bits every time. Widths below, at and above the window, odd and even; an image that is not finite
// where its reference is takes the windows of its own pixels.
TEST(Metrics, APreparedReferenceScoresEveryImageAsTheDirectSumDoes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (auto [w, h] : {std::pair{4, 9}, {11, 6}, {37, 29}, {64, 40}}) {
    FloatImage ref = filled_image(w, h, 0), other = structured(w + 3, h + 2);
    for (float& v : ref.pixels) v = uniform(rng);
    std::vector<std::uint8_t> background(ref.pixels.size(), 0);
    for (auto& b : background) b = uniform(rng) < 0.2f;
    background[static_cast<std::size_t>(h / 2) * w + w / 2] = 0;  // compared: the hole below counts
    const metrics::PreparedReference prepared(ref, background), prepared_other(other);
    FloatImage holed = with_noise(ref, 0.2, 3);
    holed.at(w / 2, h / 2) = kNaN;
    for (const FloatImage& img : {with_noise(ref, 0.1, 1), holed}) {
      const double first = metrics::compare(img, prepared).ssim;
      const double between = metrics::compare(with_noise(other, 0.1, 2), prepared_other).ssim;
      EXPECT_NEAR(first, direct_ssim(img, ref, background), 1e-9) << w << "x" << h;
      EXPECT_NEAR(between, direct_ssim(with_noise(other, 0.1, 2), other, {}), 1e-9) << w << "x" << h;
      EXPECT_EQ(metrics::compare(img, prepared).ssim, first) << w << "x" << h;
    }
  }
}

TEST(Metrics, SsimMatchesDirectWindowSum) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  auto ref = filled_image(37, 29, 0);
  for (float& v : ref.pixels) v = uniform(rng);
  auto img = with_noise(ref, 0.15, 11);
  EXPECT_NEAR(metrics::compare(img, ref).ssim, direct_ssim(img, ref, {}), 1e-6);

  // With a mask and non-finite pixels: the windows leave them out.
  std::vector<std::uint8_t> background(ref.pixels.size(), 0);
  for (auto& b : background) b = uniform(rng) < 0.2f;
  img.at(3, 4) = kNaN;
  img.at(20, 10) = kInf;
  ref.at(30, 25) = -kInf;
  auto s = metrics::compare(img, ref, background);
  double direct = direct_ssim(img, ref, background);
  EXPECT_NEAR(s.ssim, direct, 1e-6);
  EXPECT_GT(s.ssim, 0.0);
  EXPECT_LT(s.ssim, 0.9);
}

TEST(Metrics, BackgroundPixelsChangeNothing) {
  auto ref = structured(48, 32);
  auto img = with_noise(ref, 0.05, 5);
  std::vector<std::uint8_t> background(ref.pixels.size(), 0);
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) background[static_cast<std::size_t>(y) * ref.width + x] = x > 30 || y < 6;
  auto clean = metrics::compare(img, ref, background);

  auto garbage = img;  // huge errors, out-of-range and non-finite values, all under the mask
  for (std::size_t i = 0; i < garbage.pixels.size(); ++i)
    if (background[i]) garbage.pixels[i] = (i % 4 == 0) ? 1e6f : (i % 4 == 1) ? -1e6f : (i % 4 == 2) ? kNaN : kInf;
  auto s = metrics::compare(garbage, ref, background);
  expect_same_stats(s, clean);
  EXPECT_EQ(s.health.nan, 0);
  EXPECT_EQ(s.health.inf, 0);
  EXPECT_EQ(s.health.out_of_range, 0);
  long compared = std::count(background.begin(), background.end(), 0);
  EXPECT_EQ(s.health.pixels, compared);
  EXPECT_EQ(s.finite, compared);

  // Without the mask the garbage counts.
  auto unmasked = metrics::compare(garbage, ref);
  EXPECT_GT(unmasked.health.nan, 0);
  EXPECT_GT(unmasked.max, 1e5);
}

TEST(Metrics, NanAndInfAreCountedNotAveraged) {
  auto ref = structured(40, 30);
  auto img = with_noise(ref, 0.05, 9);
  auto bad = img;
  bad.at(10, 10) = kNaN;
  bad.at(25, 3) = kInf;
  bad.at(26, 3) = -kInf;
  auto s = metrics::compare(bad, ref);
  EXPECT_EQ(s.health.nan, 1);
  EXPECT_EQ(s.health.inf, 2);
  EXPECT_EQ(s.health.out_of_range, 0);
  EXPECT_EQ(s.health.pixels, 40 * 30);
  EXPECT_EQ(s.finite, 40 * 30 - 3);
  EXPECT_TRUE(std::isfinite(s.rmse) && std::isfinite(s.ssim) && std::isfinite(s.psnr));

  // Equal to the clean image with those pixels left out.
  std::vector<std::uint8_t> without(ref.pixels.size(), 0);
  without[10 * 40 + 10] = without[3 * 40 + 25] = without[3 * 40 + 26] = 1;
  expect_same_stats(s, metrics::compare(img, ref, without));

  // A non-finite reference pixel is left out too, but the image's health does not count it.
  auto bad_ref = ref;
  bad_ref.at(10, 10) = kNaN;
  auto r = metrics::compare(img, bad_ref);
  EXPECT_EQ(r.health.nan, 0);
  EXPECT_EQ(r.finite, 40 * 30 - 1);
  std::vector<std::uint8_t> one(ref.pixels.size(), 0);
  one[10 * 40 + 10] = 1;
  expect_same_stats(r, metrics::compare(img, ref, one));

  // Nothing finite to compare: NaN, not a perfect score.
  auto all_nan = filled_image(40, 30, kNaN);
  auto n = metrics::compare(all_nan, ref);
  EXPECT_EQ(n.health.nan, 40 * 30);
  EXPECT_EQ(n.finite, 0);
  EXPECT_TRUE(std::isnan(n.rmse) && std::isnan(n.ssim) && std::isnan(n.psnr));
}

TEST(Metrics, OutOfRangeValuesAreCounted) {
  auto ref = filled_image(8, 4, 0.5f);
  auto img = ref;
  img.at(0, 0) = -0.25f;  // counted
  img.at(1, 0) = 1.5f;    // counted
  img.at(2, 0) = 1.0f;    // in range
  img.at(3, 0) = 0.0f;    // in range
  img.at(4, 0) = kNaN;    // a NaN, not out of range
  img.at(5, 0) = -1e-7f;  // counted
  img.at(0, 3) = 2.0f;    // under the mask: not counted
  std::vector<std::uint8_t> background(ref.pixels.size(), 0);
  background[3 * 8 + 0] = 1;
  auto s = metrics::compare(img, ref, background);
  EXPECT_EQ(s.health.out_of_range, 3);
  EXPECT_EQ(s.health.nan, 1);
  EXPECT_EQ(s.health.inf, 0);
  EXPECT_EQ(s.health.pixels, 31);
  EXPECT_EQ(s.finite, 30);
  EXPECT_DOUBLE_EQ(s.max, 1.0);  // 1.5 - 0.5; out-of-range values are still compared
}

TEST(Metrics, ShareOverTenthIsExact) {
  auto ref = filled_image(10, 10, 0.5f);
  auto img = ref;
  std::vector<std::uint8_t> background(100, 0);
  for (int i = 0; i < 100; ++i) {
    float& v = img.pixels[i];
    if (i < 30) v = 0.625f;        // +0.125: over
    else if (i < 37) v = 0.3125f;  // -0.1875: over
    else if (i < 57) v = 0.59375f; // +0.09375: not over
    else if (i < 60) v = 0.40625f; // -0.09375: not over
  }
  auto s = metrics::compare(img, ref);
  EXPECT_DOUBLE_EQ(s.share_over_0_1, 37.0 / 100.0);
  EXPECT_DOUBLE_EQ(s.max, 0.1875);
  EXPECT_DOUBLE_EQ(s.bias, (30 * 0.125 - 7 * 0.1875 + 20 * 0.09375 - 3 * 0.09375) / 100.0);

  // Masking 10 of the +0.125 pixels and NaN-ing one -0.1875 pixel: 26 over, of 89 finite compared pixels.
  for (int i = 0; i < 10; ++i) background[i] = 1;
  img.pixels[30] = kNaN;
  s = metrics::compare(img, ref, background);
  EXPECT_EQ(s.finite, 89);
  EXPECT_DOUBLE_EQ(s.share_over_0_1, 26.0 / 89.0);
}

TEST(Metrics, SizeMismatchThrowsNamingBothSizes) {
  auto a = filled_image(4, 3, 0.5f), b = filled_image(3, 4, 0.5f);
  const std::string what = thrown_message<std::invalid_argument>([&] { metrics::compare(a, b); });
  EXPECT_NE(what.find("4x3"), std::string::npos) << what;
  EXPECT_NE(what.find("3x4"), std::string::npos) << what;
  EXPECT_THROW(metrics::compare(a, a, std::vector<std::uint8_t>(5, 0)), std::invalid_argument);
  TempDir dir;
  EXPECT_THROW(metrics::write_error_heatmap(dir / "h.png", a, b), std::invalid_argument);
  EXPECT_THROW(metrics::average(a, b), std::invalid_argument);
  EXPECT_THROW(metrics::flicker({a, b}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "h.png"));
}

TEST(Metrics, HeatmapHasDocumentedColours) {
  auto ref = filled_image(4, 3, 0.5f);
  auto img = ref;
  std::vector<std::uint8_t> background(12, 0);
  img.at(1, 0) = 0.25f;    // -0.25 = -scale: red
  img.at(2, 0) = 1.0f;     // +0.5: saturated blue
  img.at(3, 0) = 0.375f;   // -0.125: half red
  background[2 * 4 + 0] = 1;
  img.at(1, 2) = kNaN;
  ref.at(2, 2) = kInf;
  img.at(3, 2) = 0.5625f;  // +0.0625: quarter blue
  TempDir dir;
  auto path = dir / "sub" / "heat.png";
  metrics::write_error_heatmap(path, img, ref, background, 0.25);

  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  int w = 0, h = 0, channels = 0;
  unsigned char* px = stbi_load(path.string().c_str(), &w, &h, &channels, 0);
  ASSERT_NE(px, nullptr) << stbi_failure_reason();
  EXPECT_EQ(w, 4);
  EXPECT_EQ(h, 3);
  EXPECT_EQ(channels, 3);
  auto rgb = [&](int x, int y) {  // FloatImage coordinates (row 0 = bottom = last PNG row)
    const unsigned char* p = px + ((static_cast<std::size_t>(h - 1 - y) * w + x) * 3);
    return std::vector<int>{p[0], p[1], p[2]};
  };
  using C = std::vector<int>;
  EXPECT_EQ(rgb(0, 0), (C{255, 255, 255}));
  EXPECT_EQ(rgb(1, 0), (C{255, 0, 0}));
  EXPECT_EQ(rgb(2, 0), (C{0, 0, 255}));
  EXPECT_EQ(rgb(3, 0), (C{255, 128, 128}));
  EXPECT_EQ(rgb(0, 1), (C{255, 255, 255}));
  EXPECT_EQ(rgb(0, 2), (C{128, 128, 128}));
  EXPECT_EQ(rgb(1, 2), (C{0, 0, 0}));
  EXPECT_EQ(rgb(2, 2), (C{0, 0, 0}));
  EXPECT_EQ(rgb(3, 2), (C{191, 191, 255}));
  stbi_image_free(px);

  // Written atomically: only the file itself in its folder.
  int entries = 0;
  for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(path.parent_path())) ++entries;
  EXPECT_EQ(entries, 1);
  EXPECT_THROW(metrics::write_error_heatmap(path, img, ref, background, 0.0), std::invalid_argument);
}

TEST(Metrics, FlickerMeasuresFrameToFrameChange) {
  auto a = structured(20, 10);
  EXPECT_EQ(metrics::flicker({a, a, a}), 0.0);
  auto zero = filled_image(20, 10, 0.0f), one = filled_image(20, 10, 1.0f);
  EXPECT_EQ(metrics::flicker({zero, one, zero, one}), 1.0);

  // Background and non-finite pixels are left out; the pairs are pooled.
  auto b = filled_image(20, 10, 0.25f);
  std::vector<std::uint8_t> background(200, 0);
  background[0] = 1;
  b.pixels[0] = 1e6f;  // under the mask
  b.pixels[1] = kNaN;  // left out of both pairs it is in
  EXPECT_DOUBLE_EQ(metrics::flicker({zero, b, zero}, background), 0.25);
  EXPECT_THROW(metrics::flicker({zero}), std::invalid_argument);
}

TEST(Metrics, AverageIsPerPixel) {
  auto a = structured(6, 5);
  auto b = filled_image(6, 5, 0.0f);
  for (std::size_t i = 0; i < b.pixels.size(); ++i) b.pixels[i] = static_cast<float>(i) / 32.0f;
  auto m = metrics::average(a, b);
  ASSERT_EQ(m.width, 6);
  ASSERT_EQ(m.height, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 6; ++x) EXPECT_FLOAT_EQ(m.at(x, y), 0.5f * (a.at(x, y) + b.at(x, y))) << x << "," << y;
  // Average of an image with itself is the image; a NaN stays a NaN.
  a.at(2, 2) = kNaN;
  auto same = metrics::average(a, a);
  EXPECT_TRUE(std::isnan(same.at(2, 2)));
  EXPECT_EQ(same.at(1, 1), a.at(1, 1));
}

}  // namespace
}  // namespace aovar::test
