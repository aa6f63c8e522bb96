#pragma once
// Per variant, its cost on every analysed AMD family (table::GpuCosts, a cost-table row's "gpu" object):
// ACO's statistics from RADV's null device (gpu/gpu.h) and, for families with a product in the data file
// (gpu/family_specs.h), the roofline estimate (gpu/roofline.h). Sweep and measure --gpu reach it through
// gpu/by_key.h (compile by key, analyse, estimate); analyze --gpu calls it on its own analysis.
#include <map>
#include <string>
#include <vector>

#include "gpu/gpu.h"
#include "gpu/pass_loads.h"
#include "gpu/roofline.h"
#include "table/gpu_cost.h"

namespace aovar::gpu {

// Each analysed variant's pass loads (gpu/pass_loads.h), by variant key, from the render plans. `analysed`: the
// programs' SPIR-V analyses to reuse and extend across calls (pass_loads); null: this call's own.
std::map<std::string, std::vector<PassLoad>> variant_loads(const compile::CompiledSpace& compiled,
                                                           const std::vector<int>& variants,
                                                           std::map<std::string, analyze::ProgramCost>* analysed = nullptr);

// variant key -> family -> cost, from an analysis already run. A family without a spec: statistics,
// est_ms NaN. A failed family contributes the variants it completed; its error is appended to `errors`
// ("navi24: the RADV compiler crashed ...") when given.
std::map<std::string, table::GpuCosts> costs_of(const GpuAnalysis& analysis,
                                                const std::map<std::string, std::vector<PassLoad>>& loads,
                                                Frame frame, std::vector<std::string>* errors = nullptr);

}  // namespace aovar::gpu
