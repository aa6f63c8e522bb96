#pragma once
// `aovar analyze --gpu`'s outputs: the table it prints and DIR/gpu.json.
#include <string>

#include "gpu/gpu.h"

namespace aovar::gpu {

// Per family a header (device, driver), then per variant the AO pass's and the whole variant's fragment
// statistics, loops unrolled for analysis (the shipped instruction count alongside); a failed family's line.
std::string to_text(const GpuAnalysis& a);

// {"families": [{"family", "device", "driver", "error", "variants": [{"key", "passes": [{"pass", "vertex",
// "fragment", "loops_unrolled", "unrolled": {stat: value}, "shipped": {...}}], "total": {"unrolled",
// "shipped"}}]}], "pipelines"}: statistics under the driver's own names; no times (two runs compare equal).
std::string to_json(const GpuAnalysis& a);

}  // namespace aovar::gpu
