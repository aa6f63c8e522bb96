#include "gpu/roofline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

#include "gpu/gl/estimate.h"

namespace aovar::gpu {
namespace {

double stat(const ShaderStats& s, const char* name) {  // Mesa 25's unweighted counts; NaN before
  auto it = s.values.find(name);
  return it == s.values.end() ? NAN : it->second;
}

}  // namespace


table::GpuPassCost pass_statistics(const PassStats& p) {
  const ShaderStats& s = p.unrolled();
  table::GpuPassCost c;
  c.pass = p.pass;
  c.vgprs = s.vgprs;
  c.sgprs = s.sgprs;
  c.spill_vgprs = s.spill_vgprs;
  c.spill_sgprs = s.spill_sgprs;
  c.waves_per_simd = s.subgroups_per_simd;
  c.instructions = s.instructions;
  c.shipped_instructions = p.shipped().instructions;
  c.valu = stat(s, "VALU");
  c.salu = stat(s, "SALU");
  c.vmem = stat(s, "VMEM");
  c.smem = stat(s, "SMEM");
  c.latency = s.latency;
  c.inverse_throughput = s.inverse_throughput;
  c.code_size = s.code_size;
  c.alu = s.alu;
  c.texture = s.texture;
  c.memory = s.memory;
  c.registers = s.registers;
  c.occupancy = s.occupancy;
  c.spills = s.spills;
  c.cycles = s.cycles;
  c.loops = s.loops;
  c.raw = s.raw;
  return c;
}

double take_load(table::GpuPassCost& c, const PassLoad& load, Frame frame) {
  c.draws = load.draws;
  c.pixel_share = load.pixel_share;
  c.fetches = load.fetches;
  c.bytes_per_pixel = load.bytes_per_pixel;
  return double(frame.width) * frame.height * load.pixel_share * load.draws;
}

void memory_times(table::GpuPassCost& c, const PassLoad& load, double pixels, double texels_per_s, double bandwidth_gbs) {
  c.texture_ms = 1e3 * load.fetches * pixels / texels_per_s;
  c.bandwidth_ms = 1e3 * load.bytes_per_pixel * pixels / (bandwidth_gbs * 1e9);
}

void take_slowest_bound(table::GpuPassCost& c) {
  if (std::isnan(c.alu_ms)) {
    c.est_ms = NAN;
    c.bound.clear();
    return;
  }
  c.est_ms = std::max({c.alu_ms, c.texture_ms, c.bandwidth_ms});
  c.bound = c.est_ms == c.alu_ms ? "alu" : c.est_ms == c.texture_ms ? "texture" : "bandwidth";
}

void apply_roofline(table::GpuPassCost& c, const PassLoad& load, const FamilySpec& spec, Frame frame) {
  const double pixels = take_load(c, load, frame);
  const double clock_hz = spec.clock_mhz * 1e6;
  c.alu_ms = 1e3 * c.inverse_throughput * (pixels / 64.0) / (double(spec.cus) * spec.simds_per_cu * clock_hz);
  memory_times(c, load, pixels, spec.tmus * clock_hz, spec.bandwidth_gbs);
  take_slowest_bound(c);
}

table::GpuCost estimate(const VariantStats& stats, const std::vector<PassLoad>& loads, const FamilySpec* spec,
                        Frame frame, const std::string& mesa) {
  table::GpuCost cost;
  cost.product = spec ? spec->product : "";
  cost.mesa = mesa;
  cost.frame = fmt::format("{}x{}", frame.width, frame.height);
  const bool chip = spec && spec->compiler;  // a GL chip: the vendor's issue count, and the G-buffer's write
  double total = spec ? 0.0 : NAN;
  for (const PassLoad& load : loads) {
    const PassStats* p = stats.pass(load.pass);
    if (load.pass == "gbuffer") {
      // Its raster is the scene's, but its render targets' bytes are the variant's (depth format, position,
      // normal encoding): on the GL chips that write is in the frame (issue 56); AMD keeps issue 17's frame.
      if (!chip) continue;
      table::GpuPassCost c = p ? pass_statistics(*p) : table::GpuPassCost{};
      apply_gbuffer_write(c, load, *spec, frame);
      total += c.est_ms;
      cost.passes.push_back(std::move(c));
      continue;
    }
    if (!p) continue;
    table::GpuPassCost c = pass_statistics(*p);
    c.draws = load.draws;
    c.pixel_share = load.pixel_share;
    c.fetches = load.fetches;
    c.bytes_per_pixel = load.bytes_per_pixel;
    if (chip) apply_chip_roofline(c, load, *spec, frame, chip_alu_lane_cycles(*spec, p->unrolled()));
    else if (spec) apply_roofline(c, load, *spec, frame);
    total += c.est_ms;
    cost.passes.push_back(std::move(c));
  }
  cost.est_ms = total;
  return cost;
}

}  // namespace aovar::gpu
