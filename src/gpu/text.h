#pragma once
// `aovar analyze --gpu`'s outputs: the table it prints and DIR/gpu.json.
#include <map>
#include <string>

#include "gpu/gpu.h"
#include "table/gpu_cost.h"

namespace aovar::gpu {
// variant key -> family -> cost (gpu/costs.h costs_of): the estimates the outputs add when given.
using VariantCosts = std::map<std::string, table::GpuCosts>;
}  // namespace aovar::gpu

namespace aovar::gpu {

// Per family a header (device, driver), then per variant the AO pass's and the whole variant's fragment
// statistics, loops unrolled for analysis (the shipped instruction count alongside), and with `costs` the
// roofline est_ms of the variant on the family's product ("-": no product, statistics only); a failed
// family's line.
std::string to_text(const GpuAnalysis& a, const VariantCosts* costs = nullptr);

// {"families": [{"family", "device", "driver", "error", "variants": [{"key", "passes": [{"pass", "vertex",
// "fragment", "loops_unrolled", "unrolled": {stat: value}, "shipped": {...}}], "total": {"unrolled",
// "shipped"}}]}], "pipelines"}: statistics under the driver's own names; no times (two runs compare equal).
// With `costs`, each variant also has "estimate": table::to_json(GpuCost) (product, mesa, frame, est_ms,
// per pass the statistics and the three bounds), and the top level "frame".
std::string to_json(const GpuAnalysis& a, const VariantCosts* costs = nullptr);

}  // namespace aovar::gpu
