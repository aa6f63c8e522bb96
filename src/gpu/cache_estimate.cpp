#include "gpu/cache_estimate.h"

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
}

}  // namespace aovar::gpu
