#pragma once
// The roofline frame estimate of a variant on one family's product (issue 17): per pass, the time of its
// draws if ALU issue, texture-unit issue or memory bandwidth alone limited it; the pass takes the largest.
// An estimate from compiler statistics and public specs, not a measurement (docs/gpu-cost.md: its limits).
#include <string>
#include <vector>

#include "gpu/family_specs.h"
#include "gpu/gpu.h"
#include "render/frame.h"
#include "table/gpu_cost.h"

namespace aovar::gpu {

// The frame the estimate is for (the renderer's extent type); the CLI's default is 1920x1080.
using Frame = render::Extent;
inline constexpr Frame kDefaultFrame{1920, 1080};

// What one pass asks of the GPU per frame, independent of the family (gpu/pass_loads.h makes them).
struct PassLoad {
  std::string pass;
  double draws = 1;           // draws per frame
  double pixel_share = 1;     // mean share of the output's pixels one draw shades
  double fetches = 0;         // texture reads per shaded pixel (SPIR-V analyser, loops counted)
  double bytes_per_pixel = 0; // bytes read (fetches x texel size) plus render-target bytes written
};

// One pass on one product: fills draws, pixel_share, fetches, bytes_per_pixel, the three bounds, est_ms and
// bound of `cost` (its statistics already set). ALU: ACO's inverse throughput is busy SIMD cycles per 64
// invocations (aco_statistics.cpp scales by wave_size / 64), so cycles = inv_thr x pixels / 64 spread over
// CUs x SIMDs per CU at the boost clock. Texture: fetches x pixels / (TMUs x clock). Bandwidth: bytes x
// pixels / bandwidth. A statistic this Mesa does not report makes alu_ms and est_ms NaN.
void apply_roofline(table::GpuPassCost& cost, const PassLoad& load, const FamilySpec& spec, Frame frame);

// The parts of a roofline every product shares: the pass's load on `cost` and the pixels it shades in `frame`;
// the texture and bandwidth times (fetches x pixels / texel rate, bytes x pixels / bandwidth); and est_ms as the
// slowest of the three bounds with the one it is (NaN and no bound while alu_ms is unknown).
double take_load(table::GpuPassCost& cost, const PassLoad& load, Frame frame);  // returns the pixels
void memory_times(table::GpuPassCost& cost, const PassLoad& load, double pixels, double texels_per_s, double bandwidth_gbs);
void take_slowest_bound(table::GpuPassCost& cost);

// The pass's statistics (the unrolled analysis copy; shipped instructions alongside) as the table's type.
table::GpuPassCost pass_statistics(const PassStats& p);

// Every pass of `loads` the variant has statistics for, estimated on `spec` when given (nullptr: statistics
// only, est_ms NaN): an AMD family by the roofline above, a GL chip by gpu/gl/estimate.h. The G-buffer is
// left out on AMD (its cost is the scene's geometry, not the variant's); on a GL chip its render-target write
// is in (apply_gbuffer_write: the axes change it). est_ms sums the passes.
table::GpuCost estimate(const VariantStats& stats, const std::vector<PassLoad>& loads, const FamilySpec* spec,
                        Frame frame, const std::string& mesa);

}  // namespace aovar::gpu
