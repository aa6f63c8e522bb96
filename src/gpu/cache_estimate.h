#pragma once
// A pass's estimate on one product from its simulated texture traffic (issue 33): the roofline of
// gpu/roofline.h with the cache simulator's traffic (gpu/cache_sim.h, over the pass's fetch trace on a real
// view) in place of "every fetched texel comes from DRAM". docs/gpu-cost.md, "The estimate on the traffic".
#include "gpu/cache_sim.h"
#include "gpu/roofline.h"

namespace aovar::gpu {

// Sets the cache columns of `cost` (dram_bytes_per_pixel, levels, dram_ms, latency_ms) and replaces its
// texture, bandwidth and total bounds with the traffic's; `cost` must hold the pass's statistics and its
// roofline (apply_roofline) already. `traffic`: the pass's draws simulated on `spec` and merged; its per-pixel
// figures are per traced pixel, so a window stands for the whole frame.
//   texture   = reads x pixels / (TMUs x clock)                                 fetch issue
//   latency   = ACO latency x waves / (CUs x SIMDs x waves per SIMD) / clock    miss latency the occupancy hides
//   level k   = bytes through k x pixels / (instances x bytes per clock x clock)
//   dram      = DRAM bytes x pixels / memory bandwidth
//   est       = max(alu, texture, latency, every level, dram) + exposed ALU; bound names the largest.
//   exposed   = the ALU time a memory-bound pass cannot hide behind its misses (Hong and Kim 2009):
//               alu x (N - 1) / (N x reads per pixel), N the waves per SIMD; 0 when ALU is the bound.
void apply_cache_model(table::GpuPassCost& cost, const PassLoad& load, const FamilySpec& spec, Frame frame,
                       const CacheSimResult& traffic);

}  // namespace aovar::gpu
