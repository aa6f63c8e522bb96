#pragma once
// An error breakdown (metrics/breakdown.h) in words, for measure's output and the reports: the figures in one
// line, and a reading of the worst part that a person can act on, generated from the numbers.
#include <string>

#include "metrics/breakdown.h"

namespace aovar::metrics {

// "edge band 6.2 px: 9 % of the error on 17 % of the pixels (rmse 0.041, interior 0.052); far half: 64 %
// (rmse 0.061, near 0.045); too light: 81 % (mean +0.072), too dark: 19 % (mean -0.031)". NaN figures as "–".
std::string breakdown_summary(const ErrorBreakdown& b);

// Which side of each split holds the error, e.g. "spread over the interior, not the screen edges (the edge
// band holds 9 % of the error on 17 % of the pixels); mostly in the far half (64 %); mostly too light (81 %,
// mean +0.072): occluders missed". The thresholds are in breakdown_text.cpp. "no error to attribute" when
// the image equals its reference (or nothing was compared).
std::string breakdown_reading(const ErrorBreakdown& b);

}  // namespace aovar::metrics
