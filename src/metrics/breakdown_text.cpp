// The breakdown in words (see breakdown_text.h).
#include "metrics/breakdown_text.h"

#include <cmath>

#include <fmt/format.h>

namespace aovar::metrics {
namespace {

// The edge band is "where the error is" when it holds at least twice its share of the pixels: its pixels
// are then off by sqrt(2) = 1.4x the RMSE of the whole image or more, a difference a reader sees in the heat
// map. Below that the error is spread over the interior.
constexpr double kEdgeConcentration = 2.0;
// A split is "mostly" one side when that side holds 60 % of the squared error or more (near and far hold half
// the pixels each; light and dark are both possible in any pixel); closer to even it is "both".
constexpr double kMostly = 0.6;

std::string percent(double share) { return std::isnan(share) ? "–" : fmt::format("{:.0f} %", 100 * share); }
std::string number(double v) { return std::isnan(v) ? "–" : fmt::format("{:.3f}", v); }
std::string signed_number(double v) { return std::isnan(v) ? "–" : fmt::format("{:+.3f}", v); }

std::string edge_reading(const ErrorBreakdown& b) {
  const std::string figures = fmt::format("{} of the error on {} of the pixels", percent(b.edge.error_share),
                                          percent(b.edge.pixel_share));
  if (b.edge.pixel_share > 0 && b.edge.error_share >= kEdgeConcentration * b.edge.pixel_share)
    return fmt::format("concentrated in the screen-edge band ({}: taps leave the frame)", figures);
  return fmt::format("spread over the interior, not the screen edges (the edge band holds {})", figures);
}

std::string depth_reading(const ErrorBreakdown& b) {
  if (b.far.error_share >= kMostly) return fmt::format("mostly in the far half ({})", percent(b.far.error_share));
  if (b.near.error_share >= kMostly) return fmt::format("mostly in the near half ({})", percent(b.near.error_share));
  return fmt::format("even between the near and far halves ({} / {})", percent(b.near.error_share),
                     percent(b.far.error_share));
}

std::string sign_reading(const ErrorBreakdown& b) {
  if (b.light.error_share >= kMostly)
    return fmt::format("mostly too light ({}, mean {}): occluders missed", percent(b.light.error_share),
                       signed_number(b.light.mean_error));
  if (b.dark.error_share >= kMostly)
    return fmt::format("mostly too dark ({}, mean {}): over-occlusion", percent(b.dark.error_share),
                       signed_number(b.dark.mean_error));
  return fmt::format("both too light and too dark ({} / {})", percent(b.light.error_share), percent(b.dark.error_share));
}

}  // namespace

std::string breakdown_summary(const ErrorBreakdown& b) {
  return fmt::format("edge band {:.1f} px: {} of the error on {} of the pixels (rmse {}, interior {}); far half: {} "
                     "(rmse {}, near {}); too light: {} (mean {}), too dark: {} (mean {})",
                     b.edge_band_px, percent(b.edge.error_share), percent(b.edge.pixel_share), number(b.edge.rmse),
                     number(b.interior.rmse), percent(b.far.error_share), number(b.far.rmse), number(b.near.rmse),
                     percent(b.light.error_share), signed_number(b.light.mean_error), percent(b.dark.error_share),
                     signed_number(b.dark.mean_error));
}

std::string breakdown_reading(const ErrorBreakdown& b) {
  // Shares are NaN exactly when there is no squared error to share out (or no pixel was compared).
  if (std::isnan(b.light.error_share)) return "no error to attribute";
  return edge_reading(b) + "; " + depth_reading(b) + "; " + sign_reading(b);
}

}  // namespace aovar::metrics
