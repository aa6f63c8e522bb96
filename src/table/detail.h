#pragma once
// Internals shared by the cost table's JSON writer and readers and its CSV (table.cpp, json_reader.cpp,
// csv.cpp): the error fields and the breakdown's by name, the shape of an interval, the check of a round's ratios.
#include <vector>

#include "metrics/metrics.h"

namespace aovar::table::detail {

// The `error` fields of cost_table.json and the error.* CSV columns, in order.
inline constexpr const char* kErrorFields[] = {"rmse", "mae", "psnr", "ssim", "bias", "max"};
inline double& error_field(metrics::ErrorStats& e, int i) {
  double* f[] = {&e.rmse, &e.mae, &e.psnr, &e.ssim, &e.bias, &e.max};
  return *f[i];
}

// error.breakdown: its parts and each part's values by their JSON names, in file order.
struct BreakdownPart {
  const char* name;
  metrics::ErrorPart metrics::ErrorBreakdown::*part;
};
inline constexpr BreakdownPart kBreakdownParts[] = {
    {"edge", &metrics::ErrorBreakdown::edge}, {"interior", &metrics::ErrorBreakdown::interior},
    {"near", &metrics::ErrorBreakdown::near}, {"far", &metrics::ErrorBreakdown::far},
    {"light", &metrics::ErrorBreakdown::light}, {"dark", &metrics::ErrorBreakdown::dark}};
struct PartValue {
  const char* name;
  double metrics::ErrorPart::*value;
};
inline constexpr PartValue kPartValues[] = {{"pixel_share", &metrics::ErrorPart::pixel_share},
                                            {"rmse", &metrics::ErrorPart::rmse},
                                            {"error_share", &metrics::ErrorPart::error_share},
                                            {"mean_error", &metrics::ErrorPart::mean_error}};

inline constexpr const char* kIntervalShape = "an interval is [lo, hi] or null";

// Throws unless every ratio is a finite number > 0.
void check_ratios(const std::vector<double>& ratios);

}  // namespace aovar::table::detail
