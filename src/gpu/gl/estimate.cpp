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
  c.draws = load.draws;
  c.pixel_share = load.pixel_share;
  c.fetches = load.fetches;
  c.bytes_per_pixel = load.bytes_per_pixel;
  const double pixels = double(frame.width) * frame.height * load.pixel_share * load.draws;
  const double alu_lanes_per_s = chip.alu_lanes * chip.alu_clock_mhz() * 1e6;
  c.alu_ms = alu_lanes_per_s > 0 ? 1e3 * lane_cycles * pixels / alu_lanes_per_s : NAN;
  c.texture_ms = 1e3 * load.fetches * pixels / (chip.tmus * chip.clock_mhz * 1e6);
  c.bandwidth_ms = 1e3 * load.bytes_per_pixel * pixels / (chip.bandwidth_gbs * 1e9);
  if (std::isnan(c.alu_ms)) {
    c.est_ms = NAN;
    c.bound.clear();
    return;
  }
  c.est_ms = std::max({c.alu_ms, c.texture_ms, c.bandwidth_ms});
  c.bound = c.est_ms == c.alu_ms ? "alu" : c.est_ms == c.texture_ms ? "texture" : "bandwidth";
}

void apply_gbuffer_write(table::GpuPassCost& c, const PassLoad& load, const FamilySpec& chip, Frame frame) {
  c.pass = load.pass;
  c.draws = load.draws;
  c.pixel_share = load.pixel_share;
  c.fetches = load.fetches;
  c.bytes_per_pixel = load.bytes_per_pixel;
  const double pixels = double(frame.width) * frame.height * load.pixel_share * load.draws;
  c.dram_bytes_per_pixel = load.bytes_per_pixel;
  c.dram_ms = 1e3 * load.bytes_per_pixel * pixels / (chip.bandwidth_gbs * 1e9);
  c.bandwidth_ms = c.dram_ms;
  c.est_ms = c.dram_ms;
  c.bound = "dram";
}

}  // namespace aovar::gpu
