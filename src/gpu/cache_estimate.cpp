#include "gpu/cache_estimate.h"

#include <algorithm>
#include <cmath>

namespace aovar::gpu {
namespace {

int instances(const FamilySpec& spec, CacheScope scope) {
  switch (scope) {
    case CacheScope::cu: return spec.cus;
    case CacheScope::shader_array: return spec.shader_arrays();
    case CacheScope::chip: return 1;
  }
  return 1;
}

// The bound of the largest term; NaN terms (a statistic this Mesa does not report) never win.
void take(table::GpuPassCost& cost, double ms, const std::string& name) {
  if (std::isnan(ms)) return;
  if (std::isnan(cost.est_ms) || ms > cost.est_ms) {
    cost.est_ms = ms;
    cost.bound = name;
  }
}

// Hong and Kim 2009 (§4, "memory-bound" case): a wave computes between two memory instructions, and while the
// memory system serves the MWP waves in flight, the compute period of one of them per turn is not hidden:
// Comp_p x (MWP - 1) per repetition of N waves, Comp_p = compute cycles / memory instructions. Summed over the
// repetitions that is alu_ms x (MWP - 1) / (N x M). MWP is taken at its upper bound, the occupancy N (the
// model's MWP also needs a departure delay per miss, which the public specs do not give). Without it, the max
// of the roofline hides every in-core difference of a memory-bound pass: methods that read the same number of
// lines tie exactly. Zero for an ALU-bound pass; NaN where a statistic is missing.
double exposed_alu_ms(const table::GpuPassCost& cost, double reads_per_pixel) {
  if (std::isnan(cost.alu_ms) || std::isnan(cost.waves_per_simd) || cost.waves_per_simd < 1) return NAN;
  if (cost.bound == "alu" || reads_per_pixel <= 0) return 0.0;
  const double mwp = cost.waves_per_simd;
  return cost.alu_ms * (mwp - 1) / (cost.waves_per_simd * std::max(1.0, reads_per_pixel));
}

}  // namespace

void apply_cache_model(table::GpuPassCost& cost, const PassLoad& load, const FamilySpec& spec, Frame frame,
                       const CacheSimResult& traffic) {
  const double pixels = double(frame.width) * frame.height * load.pixel_share * load.draws;
  const double clock_hz = spec.clock_mhz * 1e6;
  const double per_pixel = traffic.pixels > 0 ? 1.0 / double(traffic.pixels) : 0.0;
  const double reads = double(traffic.reads) * per_pixel;

  cost.dram_bytes_per_pixel = traffic.dram_bytes_per_pixel();
  cost.texture_ms = spec.tmus > 0 ? 1e3 * reads * pixels / (spec.tmus * clock_hz) : NAN;
  const double lanes = spec.wave_size > 0 ? pixels / spec.wave_size : NAN;
  cost.latency_ms = cost.waves_per_simd > 0
                        ? 1e3 * cost.latency * lanes / (spec.cus * spec.simds_per_cu * cost.waves_per_simd) / clock_hz
                        : NAN;
  cost.levels.clear();
  cost.bandwidth_ms = NAN;
  std::string widest;
  for (std::size_t k = 0; k < traffic.levels.size() && k < spec.caches.size(); ++k) {
    const CacheLevelStats& s = traffic.levels[k];
    const CacheLevelSpec& c = spec.caches[k];
    table::GpuPassCost::Level level;
    level.name = s.name;
    level.hit_rate = s.hit_rate();
    level.bytes_per_pixel = double(s.bytes_requested) * per_pixel;
    level.ms = c.bytes_per_clock > 0
                   ? 1e3 * level.bytes_per_pixel * pixels / (instances(spec, c.scope) * c.bytes_per_clock * clock_hz)
                   : NAN;
    if (!std::isnan(level.ms) && (std::isnan(cost.bandwidth_ms) || level.ms > cost.bandwidth_ms)) {
      cost.bandwidth_ms = level.ms;
      widest = level.name;
    }
    cost.levels.push_back(level);
  }
  cost.dram_ms = spec.bandwidth_gbs > 0 ? 1e3 * cost.dram_bytes_per_pixel * pixels / (spec.bandwidth_gbs * 1e9) : NAN;
  if (!std::isnan(cost.dram_ms) && (std::isnan(cost.bandwidth_ms) || cost.dram_ms >= cost.bandwidth_ms)) {
    cost.bandwidth_ms = cost.dram_ms;
    widest = "dram";
  }

  cost.est_ms = NAN;
  cost.bound.clear();
  take(cost, cost.alu_ms, "alu");
  take(cost, cost.texture_ms, "texture");
  take(cost, cost.latency_ms, "latency");
  take(cost, cost.bandwidth_ms, widest);
  cost.exposed_alu_ms = exposed_alu_ms(cost, reads);
  if (!std::isnan(cost.exposed_alu_ms)) cost.est_ms += cost.exposed_alu_ms;
}

}  // namespace aovar::gpu
