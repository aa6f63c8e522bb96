#include "gpu/text.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace aovar::gpu {
namespace {

std::string num(double v) { return std::isnan(v) ? "-" : fmt::format("{:.0f}", v); }

std::string row(const std::string& variant, const std::string& what, const ShaderStats& s, double shipped_instr) {
  return fmt::format("{:<44} {:<6} {:>5} {:>5} {:>6} {:>5} {:>6} {:>7} {:>5} {:>8} {:>7} {:>6}\n", variant, what,
                     num(s.vgprs), num(s.sgprs), num(s.spill_vgprs + s.spill_sgprs), num(s.subgroups_per_simd),
                     num(s.instructions), num(shipped_instr), num(s.vmem_clauses), num(s.latency),
                     num(s.inverse_throughput), num(s.code_size));
}

std::string family_text(const FamilyStats& f) {
  std::string out = fmt::format("{}: {} ({})\n", f.family, f.device.empty() ? "no device" : f.device,
                                f.driver.empty() ? "driver unknown" : f.driver);
  if (!f.variants.empty()) {
    out += fmt::format("{:<44} {:<6} {:>5} {:>5} {:>6} {:>5} {:>6} {:>7} {:>5} {:>8} {:>7} {:>6}\n", "variant",
                       "pass", "VGPR", "SGPR", "spills", "waves", "instr", "shipped", "VMEM", "latency", "inv.thr",
                       "code");
    for (const VariantStats& v : f.variants) {
      if (const PassStats* ao = v.pass("ao")) out += row(v.key, "ao", ao->unrolled, ao->shipped.instructions);
      out += row(v.pass("ao") ? "" : v.key, "total", v.total(true), v.total(false).instructions);
    }
  }
  if (!f.ok()) out += fmt::format("{}: FAILED: {} ({} variants complete)\n", f.family, f.error, f.variants.size());
  return out;
}

nlohmann::json pass_json(const PassStats& p) {
  return {{"pass", p.pass},
          {"vertex", p.vertex},
          {"fragment", p.fragment},
          {"loops_unrolled", p.loops_unrolled},
          {"unrolled", to_json(p.unrolled)},
          {"shipped", to_json(p.shipped)}};
}

}  // namespace

std::string to_text(const GpuAnalysis& a) {
  std::string out = "fragment-stage statistics from RADV's null device (ACO), loops unrolled for analysis; "
                    "'shipped' = instructions of the module as shipped; waves = subgroups per SIMD; "
                    "total = every pass once (registers and waves: the worst pass)\n";
  for (const FamilyStats& f : a.families) out += "\n" + family_text(f);
  int failed = 0;
  for (const FamilyStats& f : a.families) failed += f.ok() ? 0 : 1;
  out += fmt::format("\n{} families ({} failed), {} distinct pipelines each, {:.1f} s\n", a.families.size(), failed,
                     a.pipelines, a.seconds);
  return out;
}

std::string to_json(const GpuAnalysis& a) {
  nlohmann::json families = nlohmann::json::array();
  for (const FamilyStats& f : a.families) {
    nlohmann::json variants = nlohmann::json::array();
    for (const VariantStats& v : f.variants) {
      nlohmann::json passes = nlohmann::json::array();
      for (const PassStats& p : v.passes) passes.push_back(pass_json(p));
      variants.push_back({{"key", v.key},
                          {"passes", passes},
                          {"total", {{"unrolled", to_json(v.total(true))}, {"shipped", to_json(v.total(false))}}}});
    }
    families.push_back({{"family", f.family},
                        {"device", f.device},
                        {"driver", f.driver},
                        {"error", f.error},
                        {"variants", variants}});
  }
  nlohmann::json j{{"source", "RADV null device, fragment executable, VK_KHR_pipeline_executable_properties"},
                   {"pipelines", a.pipelines},
                   {"families", families}};
  return j.dump(1) + "\n";
}

}  // namespace aovar::gpu
