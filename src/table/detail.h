#pragma once
// Internals shared by the cost table's JSON writer and readers and its CSV (table.cpp, json_reader.cpp,
// csv.cpp): the error fields by name, the shape of an interval, the check of a round's ratios.
#include <vector>

#include "metrics/metrics.h"

namespace aovar::table::detail {

// The `error` fields of cost_table.json and the error.* CSV columns, in order.
inline constexpr const char* kErrorFields[] = {"rmse", "mae", "psnr", "ssim", "bias", "max"};
inline double& error_field(metrics::ErrorStats& e, int i) {
  double* f[] = {&e.rmse, &e.mae, &e.psnr, &e.ssim, &e.bias, &e.max};
  return *f[i];
}

inline constexpr const char* kIntervalShape = "an interval is [lo, hi] or null";

// Throws unless every ratio is a finite number > 0.
void check_ratios(const std::vector<double>& ratios);

}  // namespace aovar::table::detail
