#pragma once
// The frame-time estimate of one pass on a GL chip (NVIDIA, Adreno, Mali, Intel; issue 56): the roofline of
// gpu/roofline.h with its ALU term from the vendor's own issue count (GlVendor::alu_lane_cycles) instead of
// ACO's inverse throughput. The traced cache model (gpu/cache_estimate.h) then replaces the texture and memory
// terms as on AMD. docs/gpu-cost.md, "The estimate on the GL chips".
#include "gpu/family_specs.h"
#include "gpu/roofline.h"
#include "gpu/stats.h"
#include "table/gpu_cost.h"

namespace aovar::gpu {

// The lane-cycles one pixel of this pass takes on `chip`'s ALUs (its vendor's count); NaN when unknown.
double chip_alu_lane_cycles(const FamilySpec& chip, const ShaderStats& stats);

// Fills draws, pixel_share, fetches, bytes_per_pixel, the three bounds, est_ms and bound of `cost`:
//   alu_ms       = lane-cycles x pixels / (alu_lanes x ALU clock)       issue
//   texture_ms   = fetches x pixels / (TMUs x clock)                      texel rate
//   bandwidth_ms = bytes x pixels / memory bandwidth                      every byte from DRAM (no trace)
//   est_ms       = the largest; a missing count makes alu_ms and est_ms NaN.
void apply_chip_roofline(table::GpuPassCost& cost, const PassLoad& load, const FamilySpec& chip, Frame frame,
                         double lane_cycles);

// The G-buffer pass as the variant changes it: the bytes of its render targets written once per pixel (a tiler
// writes them when it resolves a tile, an immediate renderer as it shades; overdraw is the scene's, not the
// variant's), at the memory bandwidth. The raster and the geometry stay outside, as on AMD. bound "dram".
void apply_gbuffer_write(table::GpuPassCost& cost, const PassLoad& load, const FamilySpec& chip, Frame frame);

}  // namespace aovar::gpu
