#include "gpu/text.h"
#include "util/schema.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace aovar::gpu {
namespace {

std::string num(double v) { return std::isnan(v) ? "-" : fmt::format("{:.0f}", v); }

std::string ms(double v) { return std::isnan(v) ? "-" : fmt::format("{:.3f}", v); }

std::string row(const std::string& variant, const std::string& what, const ShaderStats& s, double shipped_instr,
                const std::string& est) {
  return fmt::format("{:<44} {:<6} {:>5} {:>5} {:>6} {:>5} {:>6} {:>7} {:>5} {:>8} {:>7} {:>6} {:>7}\n", variant,
                     what, num(s.vgprs), num(s.sgprs), num(s.spill_vgprs + s.spill_sgprs), num(s.subgroups_per_simd),
                     num(s.instructions), num(shipped_instr), num(s.vmem_clauses), num(s.latency),
                     num(s.inverse_throughput), num(s.code_size), est);
}

const table::GpuCost* cost_of(const VariantCosts* costs, const std::string& variant, const std::string& family) {
  if (!costs) return nullptr;
  auto v = costs->find(variant);
  if (v == costs->end()) return nullptr;
  auto f = v->second.find(family);
  return f == v->second.end() ? nullptr : &f->second;
}

std::string family_text(const FamilyStats& f, const VariantCosts* costs) {
  std::string out = fmt::format("{}: {} ({})\n", f.family, f.device.empty() ? "no device" : f.device,
                                f.driver.empty() ? "driver unknown" : f.driver);
  if (!f.variants.empty()) {
    const table::GpuCost* first = f.variants.empty() ? nullptr : cost_of(costs, f.variants[0].key, f.family);
    if (first && !first->product.empty())
      out += fmt::format("est_ms: roofline on {} at {}, G-buffer excluded (docs/gpu-cost.md)\n", first->product,
                         first->frame);
    out += fmt::format("{:<44} {:<6} {:>5} {:>5} {:>6} {:>5} {:>6} {:>7} {:>5} {:>8} {:>7} {:>6} {:>7}\n", "variant",
                       "pass", "VGPR", "SGPR", "spills", "waves", "instr", "shipped", "VMEM", "latency", "inv.thr",
                       "code", "est_ms");
    for (const VariantStats& v : f.variants) {
      const table::GpuCost* c = cost_of(costs, v.key, f.family);
      const table::GpuPassCost* ao_cost = c ? c->pass("ao") : nullptr;
      if (const PassStats* ao = v.pass("ao"))
        out += row(v.key, "ao", ao->unrolled, ao->shipped.instructions, ms(ao_cost ? ao_cost->est_ms : NAN));
      out += row(v.pass("ao") ? "" : v.key, "total", v.total(true), v.total(false).instructions,
                 ms(c ? c->est_ms : NAN));
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

std::string to_text(const GpuAnalysis& a, const VariantCosts* costs) {
  std::string out = "fragment-stage statistics from RADV's null device (ACO), loops unrolled for analysis; "
                    "'shipped' = instructions of the module as shipped; waves = subgroups per SIMD; "
                    "total = every pass once (registers and waves: the worst pass)\n";
  for (const FamilyStats& f : a.families) out += "\n" + family_text(f, costs);
  int failed = 0;
  for (const FamilyStats& f : a.families) failed += f.ok() ? 0 : 1;
  out += fmt::format("\n{} families ({} failed), {} distinct pipelines each, {:.1f} s\n", a.families.size(), failed,
                     a.pipelines, a.seconds);
  return out;
}

std::string to_json(const GpuAnalysis& a, const VariantCosts* costs) {
  nlohmann::json families = nlohmann::json::array();
  for (const FamilyStats& f : a.families) {
    nlohmann::json variants = nlohmann::json::array();
    for (const VariantStats& v : f.variants) {
      nlohmann::json passes = nlohmann::json::array();
      for (const PassStats& p : v.passes) passes.push_back(pass_json(p));
      nlohmann::json entry = {{"key", v.key},
                              {"passes", passes},
                              {"total", {{"unrolled", to_json(v.total(true))}, {"shipped", to_json(v.total(false))}}}};
      if (const table::GpuCost* c = cost_of(costs, v.key, f.family)) entry["estimate"] = table::to_json(*c);
      variants.push_back(std::move(entry));
    }
    families.push_back({{"family", f.family},
                        {"device", f.device},
                        {"driver", f.driver},
                        {"error", f.error},
                        {"variants", variants}});
  }
  nlohmann::json j{{"schema_version", util::kSchemaVersion},
                   {"source", "RADV null device, fragment executable, VK_KHR_pipeline_executable_properties"},
                   {"pipelines", a.pipelines},
                   {"families", families}};
  if (costs && !costs->empty() && !costs->begin()->second.empty())  // one frame for the whole run
    j["frame"] = costs->begin()->second.begin()->second.frame;
  return j.dump(1) + "\n";
}

}  // namespace aovar::gpu
