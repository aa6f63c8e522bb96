#pragma once
// Internals shared by the cost table's JSON and CSV (table.cpp, csv.cpp): the error fields by name.
#include "metrics/metrics.h"

namespace aovar::table::detail {

// The `error` fields of cost_table.json and the error.* CSV columns, in order.
inline constexpr const char* kErrorFields[] = {"rmse", "mae", "psnr", "ssim", "bias", "max"};
inline double& error_field(metrics::ErrorStats& e, int i) {
  double* f[] = {&e.rmse, &e.mae, &e.psnr, &e.ssim, &e.bias, &e.max};
  return *f[i];
}

}  // namespace aovar::table::detail
