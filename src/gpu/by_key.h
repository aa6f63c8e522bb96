#pragma once
// GPU costs of variants named by key, for `sweep --gpu` and `measure --gpu`: compiles them for Vulkan
// (through the compile cache: measure compiled them already), analyses every pass on RADV's null device of
// each family and estimates it (gpu/costs.h). A family that fails (a compiler crash) leaves the others'
// costs and is named in `errors`.
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "compile/run_scope.h"
#include "render/frame.h"
#include "table/gpu_cost.h"
#include "variants/manifest.h"

namespace aovar::gpu {

struct CostRequest {
  compile::RunScope scope;            // the manifest, compile jobs, the cache root
  std::vector<std::string> families;  // empty: nothing to do
  render::Extent frame{1920, 1080};    // the frame the estimate is for
  variants::CalibratedValues calibration;  // the parameter values the variants render with (GpuOptions)
};

struct KeyedCosts {
  std::map<std::string, table::GpuCosts> by_variant;  // key -> family -> cost
  std::vector<std::string> errors;                     // one line per family that failed
  std::string mesa;                                    // the RADV that compiled them ("Mesa 25.0.7-...")
  int pipelines = 0;
  double seconds = 0;
};

// Before any work (a sweep measures for minutes first): throws std::runtime_error, one line, for a missing
// driver or a family this RADV does not know. Nothing when no family is asked for.
void check_gpus(const std::vector<std::string>& names);

// Throws std::runtime_error for a missing driver, an unknown family or a program that does not compile.
KeyedCosts costs_by_key(const CostRequest& request, const std::set<std::string>& keys);

}  // namespace aovar::gpu
