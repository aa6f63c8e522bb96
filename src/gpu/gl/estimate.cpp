#include "gpu/gl/estimate.h"

#include <algorithm>
#include <cmath>

#include "gpu/gl/vendor.h"

namespace aovar::gpu {

double chip_alu_lane_cycles(const FamilySpec& chip, const ShaderStats& stats) {
  const GlVendor* vendor = chip.compiler ? gl_vendor(chip.compiler->driver) : nullptr;
  return vendor && vendor->alu_lane_cycles ? vendor->alu_lane_cycles(stats) : NAN;
}

void apply_chip_roofline(table::GpuPassCost& c, const PassLoad& load, const FamilySpec& chip, Frame frame,
                         double lane_cycles) {
  const double pixels = take_load(c, load, frame);
  const double alu_lanes_per_s = chip.alu_lanes * chip.alu_clock_mhz() * 1e6;
  c.alu_ms = alu_lanes_per_s > 0 ? 1e3 * lane_cycles * pixels / alu_lanes_per_s : NAN;
  memory_times(c, load, pixels, chip.tmus * chip.clock_mhz * 1e6, chip.bandwidth_gbs);
  take_slowest_bound(c);
}

void apply_gbuffer_write(table::GpuPassCost& c, const PassLoad& load, const FamilySpec& chip, Frame frame) {
  c.pass = load.pass;
  const double pixels = take_load(c, load, frame);
  c.dram_bytes_per_pixel = load.bytes_per_pixel;
  c.dram_ms = 1e3 * load.bytes_per_pixel * pixels / (chip.bandwidth_gbs * 1e9);
  c.bandwidth_ms = c.dram_ms;
  c.est_ms = c.dram_ms;
  c.bound = "dram";
}

}  // namespace aovar::gpu
