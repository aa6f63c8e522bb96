// Intel through Mesa's brw compiler (crocus for Gen4-7 such as Bay Trail, iris for Gen8 and later): "FS SIMD8
// shader: 465 inst, 0 loops, 11046 cycles, 0:0 spills:fills, 11 sends, ...", one line per SIMD width compiled.
// Natively on amd64; the noop shim is not packaged by Debian and is built from Mesa's source (scripts/intel-shim).
// The widest width compiled is the one read: the hardware dispatches it whenever it was compiled (a width that
// would spill is not compiled at all). brw reports these lines through KHR_debug whatever INTEL_DEBUG says;
// INTEL_DEBUG=fs would add the whole disassembly on stderr (hundreds of MB over the default space), so it is
// left unset.
#include <regex>

#include "gpu/gl/vendor.h"

namespace aovar::gpu {
namespace {

std::optional<ShaderStats> intel_fragment_stats(const std::vector<std::string>& messages) {
  static const std::regex head(R"(FS SIMD([0-9]+) shader:(.*))");
  std::optional<ShaderStats> widest;
  for (const std::string& line : messages) {
    std::smatch m;
    if (!std::regex_search(line, m, head)) continue;
    const double width = std::stod(m[1]);
    if (widest && widest->values["simd"] >= width) continue;
    auto values = counted_fields(m[2]);
    values["simd"] = width;
    ShaderStats s = line_stats(std::move(values), line);
    s.memory = field(s.values, "sends");  // every message: sampler, data port and render-target writes
    s.spills = field(s.values, "spills");
    s.loops = field(s.values, "loops");
    s.cycles = field(s.values, "cycles");  // brw's static estimate for one SIMD-width thread
    widest = std::move(s);
  }
  return widest;
}

}  // namespace

// ALU term: instructions_issued, brw's instructions of the widest dispatch compiled: a SIMD-N instruction takes
// N / 8 clocks on an EU's eight fp32 lanes (two SIMD-4 FPUs, Gen7.5 white paper), one lane-cycle per pixel.
// `cycles` is brw's latency estimate of one thread alone, which the EU's other threads hide: not a throughput.
const GlVendor& intel_vendor() {
  static const GlVendor v{"intel", "Intel (crocus, iris)", "amd64", "libintel_noop_drm_shim.so",
                          "INTEL_STUB_GPU_PLATFORM", {}, intel_fragment_stats, instructions_issued};
  return v;
}

}  // namespace aovar::gpu
