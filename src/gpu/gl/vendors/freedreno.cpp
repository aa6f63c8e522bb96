// Qualcomm Adreno through freedreno's ir3 (a3xx to a7xx): with FD_MESA_DEBUG=shaderdb, "FRAG shader: 826 inst,
// 340 nops, 486 non-nops, ... 0 half, 8 full, 39 constlen, ... 16 cat5, ... 12 waves, 0 loops". Debian builds
// freedreno only for arm: its arm64 packages run under qemu-user. ir3's instruction categories: cat0 flow and
// nops, cat1 moves, cat2-cat4 arithmetic (cat4 the transcendental unit), cat5 texture, cat6 memory.
#include "gpu/gl/vendor.h"

namespace aovar::gpu {
namespace {

// `instructions` is ir3's `inst`, nops included: ir3 issues them as delay slots.
std::optional<ShaderStats> freedreno_fragment_stats(const std::vector<std::string>& messages) {
  auto s = tagged_line_stats(messages, "FRAG shader:");
  if (!s) return s;
  s->alu = field_sum(s->values, {"cat1", "cat2", "cat3", "cat4"});
  s->texture = field(s->values, "cat5");
  s->memory = field(s->values, "cat6");
  // A half register is half a full one in the register file (ir3: two halves share a full register).
  s->registers = field(s->values, "full") + 0.5 * field(s->values, "half");
  s->occupancy = field(s->values, "waves");
  s->loops = field(s->values, "loops");
  return s;
}

}  // namespace

// ALU term: instructions_issued. ir3 is a scalar ISA issued in order; `inst` counts the nops ir3 schedules as
// delay slots, which occupy the issue slot as any instruction does (the hardware has no interlock for ALU results).
const GlVendor& freedreno_vendor() {
  static const GlVendor v{"freedreno", "Qualcomm Adreno (freedreno)", "arm64", "libfreedreno_noop_drm_shim.so",
                          "FD_GPU_ID", {{"FD_MESA_DEBUG", "shaderdb"}}, freedreno_fragment_stats,
                          instructions_issued};
  return v;
}

}  // namespace aovar::gpu
