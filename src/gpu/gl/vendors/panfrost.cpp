// Arm Mali through panfrost: Midgard (T6xx-T8xx), "MESA_SHADER_FRAGMENT shader: 349 inst, 176 bundles, 301
// quadwords, 8 registers, 2 threads, 0 loops, 0:0 spills:fills"; Bifrost and Valhall (G31 and later) add
// malioc-like cycle estimates ("15.83 cycles, 15.83 arith, 4.5 texture, ..."). Debian builds panfrost only for
// arm: its arm64 packages run under qemu-user. Both compilers print with their *_MESA_DEBUG=shaderdb.
#include <cmath>

#include "gpu/gl/vendor.h"

namespace aovar::gpu {
namespace {

std::optional<ShaderStats> panfrost_fragment_stats(const std::vector<std::string>& messages) {
  auto s = tagged_line_stats(messages, "MESA_SHADER_FRAGMENT shader:");
  if (!s) return s;
  s->registers = field(s->values, "registers");
  s->occupancy = field(s->values, "threads");
  s->spills = field(s->values, "spills");
  s->loops = field(s->values, "loops");
  s->cycles = field(s->values, "cycles");  // Bifrost and Valhall only: the bound of arith, texture, ldst, varying
  return s;
}

// Midgard issues one VLIW bundle per clock per arithmetic pipe for one thread (Arm, "The Midgard Shader Core"):
// its `bundles` are the pipe-cycles of a pixel (texture and load/store bundles, which run on their own pipes,
// included: an overcount). Valhall issues warp instructions on 16-lane units: `inst` per thread.
double panfrost_alu_lane_cycles(const ShaderStats& s) {
  const double bundles = field(s.values, "bundles");
  return std::isnan(bundles) ? s.instructions : bundles;
}

}  // namespace

const GlVendor& panfrost_vendor() {
  static const GlVendor v{"panfrost", "Arm Mali (panfrost)", "arm64", "libpanfrost_noop_drm_shim.so", "PAN_GPU_ID",
                          {{"MIDGARD_MESA_DEBUG", "shaderdb"}, {"BIFROST_MESA_DEBUG", "shaderdb"}},
                          panfrost_fragment_stats, panfrost_alu_lane_cycles};
  return v;
}

}  // namespace aovar::gpu
