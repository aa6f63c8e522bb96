// NVIDIA through nouveau's codegen (Tesla GT200 to Ada): "type: 4, local: 0, shared: 0, gpr: 29, inst: 451,
// bytes: 3608" (+ "loops: 1" on Tesla), one line per shader; type 4 is the fragment program
// (nv50_ir::Program::TYPE_FRAGMENT). Natively on amd64 from Debian's mesa-libgallium and mesa-drm-shim.
// nouveau reports no texture or ALU split and no cycles: those stay NaN.
#include <regex>

#include "gpu/gl/vendor.h"

namespace aovar::gpu {
namespace {

std::optional<ShaderStats> nouveau_fragment_stats(const std::vector<std::string>& messages) {
  static const std::regex pair(R"(([a-z_]+):\s*(-?[0-9]+))");
  const std::string* line = last_line_with(messages, "type: 4,");
  if (!line) return std::nullopt;
  std::map<std::string, double> values;
  for (auto it = std::sregex_iterator(line->begin(), line->end(), pair); it != std::sregex_iterator(); ++it)
    values[(*it)[1]] = std::stod((*it)[2]);
  values.erase("type");
  values.erase("cached");  // a pointer-ish cache key, not a statistic
  ShaderStats s = line_stats(std::move(values), *line);
  s.registers = field(s.values, "gpr");
  s.loops = field(s.values, "loops");
  return s;
}

}  // namespace

// ALU term: instructions_issued. nv50 ir issues one instruction per thread per clock on a CUDA core (a warp of 32
// over the SM's cores); the texture and memory instructions take an issue slot too. No ALU split is reported, so
// every instruction counts.
const GlVendor& nouveau_vendor() {
  static const GlVendor v{"nouveau", "NVIDIA (nouveau)", "amd64", "libnouveau_noop_drm_shim.so", "NOUVEAU_CHIPSET",
                          {}, nouveau_fragment_stats, instructions_issued};
  return v;
}

}  // namespace aovar::gpu
