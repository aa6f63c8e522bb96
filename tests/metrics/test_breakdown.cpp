// Where the error comes from (metrics/breakdown.h): synthetic images whose split is known by hand — an error
// only in the edge band, only in the far half, only too light — the empty and NaN cases, the reading in words,
// and the reference's depth (the same as trace_depth's, kept by the cache).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "metrics/breakdown.h"
#include "metrics/breakdown_text.h"
#include "render_support.h"
#include "runner/score.h"
#include "test_support.h"

namespace aovar::test {
namespace {

using image::FloatImage;


// 10 x 10, depth 1 on the left half (x < 5) and 2 on the right: the median (lower, nearest rank) is 1.
FloatImage two_depths() {
  FloatImage d = filled_image(10, 10, 1.0f);
  for (int y = 0; y < 10; ++y)
    for (int x = 5; x < 10; ++x) d.at(x, y) = 2.0f;
  return d;
}

// All of the error in the part `hit` (`pixel_share` of the compared pixels, each off by `off`), none in `clean`,
// which holds the other pixels; `what` names the split in a failure.
void expect_all_error_in(const metrics::ErrorPart& hit, const metrics::ErrorPart& clean, double pixel_share, double off,
                         const char* what) {
  EXPECT_DOUBLE_EQ(hit.pixel_share, pixel_share) << what;
  EXPECT_DOUBLE_EQ(clean.pixel_share, 1 - pixel_share) << what;
  EXPECT_DOUBLE_EQ(hit.error_share, 1.0) << what;
  EXPECT_DOUBLE_EQ(clean.error_share, 0.0) << what;
  EXPECT_NEAR(hit.rmse, off, 1e-6) << what;
  EXPECT_DOUBLE_EQ(clean.rmse, 0.0) << what;
}

TEST(Breakdown, ErrorOnlyInTheEdgeBand) {
  // Band 1 px on a 10 x 10 image: the outer ring, 100 - 8 * 8 = 36 pixels, off by +0.2.
  const FloatImage ref = filled_image(10, 10, 0.5f);
  FloatImage img = ref;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      if (std::min({x, y, 9 - x, 9 - y}) < 1) img.at(x, y) = 0.7f;
  const auto b = metrics::error_breakdown(img, ref, {}, two_depths(), 1.0);
  EXPECT_DOUBLE_EQ(b.edge_band_px, 1.0);
  expect_all_error_in(b.edge, b.interior, 0.36, 0.2, "edge / interior");
  EXPECT_NEAR(b.edge.mean_error, 0.2, 1e-6);
  // A band of 1.4 px still holds one ring (the second ring's centres are 1.5 px in), 2 holds two, 0 none.
  EXPECT_DOUBLE_EQ(metrics::error_breakdown(img, ref, {}, two_depths(), 1.4).edge.pixel_share, 0.36);
  EXPECT_DOUBLE_EQ(metrics::error_breakdown(img, ref, {}, two_depths(), 2.0).edge.pixel_share, 0.64);
  const auto none = metrics::error_breakdown(img, ref, {}, two_depths(), 0.0);
  EXPECT_DOUBLE_EQ(none.edge.pixel_share, 0.0);
  EXPECT_TRUE(std::isnan(none.edge.rmse));
  EXPECT_DOUBLE_EQ(none.interior.error_share, 1.0);
  // 100 % of the error on 36 % of the pixels: concentrated there.
  EXPECT_NE(metrics::breakdown_reading(b).find("concentrated in the screen-edge band (100 % of the error on 36 % of the pixels"),
            std::string::npos)
      << metrics::breakdown_reading(b);
}

TEST(Breakdown, ErrorOnlyInTheFarHalfAndTooLight) {
  const FloatImage ref = filled_image(10, 10, 0.5f), depth = two_depths();
  FloatImage img = ref;
  for (int y = 0; y < 10; ++y)
    for (int x = 5; x < 10; ++x) img.at(x, y) = 0.8f;  // the far half, lighter by 0.3
  const auto b = metrics::error_breakdown(img, ref, {}, depth, 0.0);
  EXPECT_EQ(b.split_depth, 1.0);
  expect_all_error_in(b.far, b.near, 0.5, 0.3, "far / near");
  // Too light everywhere it is wrong: all of the error, the far pixels' +0.3 as its mean; nothing too dark.
  EXPECT_DOUBLE_EQ(b.light.error_share, 1.0);
  EXPECT_DOUBLE_EQ(b.light.pixel_share, 0.5);
  EXPECT_NEAR(b.light.mean_error, 0.3, 1e-6);
  EXPECT_DOUBLE_EQ(b.dark.pixel_share, 0.0);
  EXPECT_DOUBLE_EQ(b.dark.error_share, 0.0);
  EXPECT_TRUE(std::isnan(b.dark.mean_error));
  const std::string reading = metrics::breakdown_reading(b);
  EXPECT_NE(reading.find("mostly in the far half (100 %)"), std::string::npos) << reading;
  EXPECT_NE(reading.find("mostly too light (100 %, mean +0.300): occluders missed"), std::string::npos) << reading;
  EXPECT_NE(reading.find("spread over the interior"), std::string::npos) << reading;
}

TEST(Breakdown, LightAndDarkShareTheSquaredError) {
  // Four pixels: +0.1, -0.2, -0.2, exact. Squared: 0.01, 0.04, 0.04 -> light 1/9, dark 8/9.
  const FloatImage ref = filled_image(2, 2, 0.5f);
  FloatImage img = ref;
  img.pixels = {0.6f, 0.3f, 0.3f, 0.5f};
  const auto b = metrics::error_breakdown(img, ref, {}, filled_image(2, 2, 1.0f), 0.0);
  EXPECT_NEAR(b.light.error_share, 1.0 / 9, 1e-6);
  EXPECT_NEAR(b.dark.error_share, 8.0 / 9, 1e-6);
  EXPECT_DOUBLE_EQ(b.light.pixel_share, 0.25);
  EXPECT_DOUBLE_EQ(b.dark.pixel_share, 0.5);
  EXPECT_NEAR(b.dark.mean_error, -0.2, 1e-6);
  EXPECT_NE(metrics::breakdown_reading(b).find("mostly too dark (89 %, mean -0.200): over-occlusion"), std::string::npos)
      << metrics::breakdown_reading(b);
  // One depth everywhere: every pixel is near (<= the median), the far half is empty.
  EXPECT_DOUBLE_EQ(b.near.pixel_share, 1.0);
  EXPECT_DOUBLE_EQ(b.far.pixel_share, 0.0);
  EXPECT_TRUE(std::isnan(b.far.rmse));
}

TEST(Breakdown, BackgroundAndNonFinitePixelsAreLeftOut) {
  // Background and NaN pixels carry huge "errors" that must change nothing; a compared pixel without a finite
  // depth is in neither half.
  const FloatImage ref = filled_image(4, 1, 0.5f);
  FloatImage img = ref;
  img.pixels = {0.7f, 0.0f, kNaN, 0.5f};
  FloatImage depth = filled_image(4, 1, 1.0f);
  depth.pixels[3] = kInf;
  const std::vector<std::uint8_t> background = {0, 1, 0, 0};
  const auto b = metrics::error_breakdown(img, ref, background, depth, 0.0);
  EXPECT_DOUBLE_EQ(b.interior.pixel_share, 1.0);  // pixels 0 and 3 entered
  EXPECT_DOUBLE_EQ(b.light.error_share, 1.0);
  EXPECT_DOUBLE_EQ(b.near.pixel_share, 0.5);  // pixel 3 has no depth
  EXPECT_DOUBLE_EQ(b.far.pixel_share, 0.0);
  EXPECT_EQ(metrics::median_depth(depth, background), 1.0);
}

TEST(Breakdown, EmptyAndIdenticalAreNaNNotZero) {
  const FloatImage ref = filled_image(3, 3, 0.5f);
  // Nothing compared: every figure NaN.
  const auto empty = metrics::error_breakdown(ref, ref, std::vector<std::uint8_t>(9, 1), filled_image(3, 3, 1.0f), 1.0);
  EXPECT_TRUE(std::isnan(empty.edge.pixel_share));
  EXPECT_TRUE(std::isnan(empty.far.rmse));
  EXPECT_TRUE(std::isnan(empty.split_depth));
  EXPECT_EQ(metrics::breakdown_reading(empty), "no error to attribute");
  // Identical: pixel shares known, no squared error to share out.
  const auto same = metrics::error_breakdown(ref, ref, {}, filled_image(3, 3, 1.0f), 1.0);
  EXPECT_DOUBLE_EQ(same.edge.pixel_share, 8.0 / 9);
  EXPECT_TRUE(std::isnan(same.edge.error_share));
  EXPECT_DOUBLE_EQ(same.interior.rmse, 0.0);
  EXPECT_EQ(metrics::breakdown_reading(same), "no error to attribute");
  const auto nothing = metrics::error_breakdown({0, 0, {}}, {0, 0, {}}, {}, {0, 0, {}}, 0.0);
  EXPECT_TRUE(std::isnan(nothing.light.pixel_share));
  EXPECT_TRUE(std::isnan(metrics::median_depth({0, 0, {}})));
}

TEST(Breakdown, BadInputIsAnErrorNamingIt) {
  const FloatImage a = filled_image(3, 3, 0.5f);
  EXPECT_THROW(metrics::error_breakdown(a, a, {}, filled_image(2, 3, 1.0f), 1.0), std::invalid_argument);
  EXPECT_THROW(metrics::error_breakdown(a, a, {}, filled_image(3, 3, 1.0f), -1.0), std::invalid_argument);
  EXPECT_THROW(metrics::error_breakdown(a, a, {}, filled_image(3, 3, 1.0f), kNaN), std::invalid_argument);
  try {
    metrics::error_breakdown(a, a, {1, 0}, filled_image(3, 3, 1.0f), 1.0);
    ADD_FAILURE() << "a short mask must throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("background mask has 2 entries"), std::string::npos) << e.what();
  }
}

// The band runner::score uses: the AO radius in pixels at the median depth, radius * P11 / 2 * height / z,
// capped at a quarter of the shorter side; 0 without geometry.
TEST(Breakdown, EdgeBandIsTheRadiusInPixelsAtTheMedianDepth) {
  scene::View view;
  view.fov_y_deg = 90.0f;  // P11 = 1
  view.near_plane = 0.1f;
  view.far_plane = 100.0f;
  view.eye = {0, 0, 5};
  view.target = {0, 0, 0};
  view.up = {0, 1, 0};
  // 0.5 * 1 * 0.5 * 200 / 10 = 5 px.
  EXPECT_NEAR(runner::edge_band_px(view, 0.5f, {400, 200}, 10.0), 5.0, 1e-4);
  EXPECT_NEAR(runner::edge_band_px(view, 0.5f, {400, 200}, 0.01), 50.0, 1e-9) << "capped at 200 / 4";
  EXPECT_EQ(runner::edge_band_px(view, 0.5f, {400, 200}, std::nan("")), 0.0);
}

}  // namespace
}  // namespace aovar::test
