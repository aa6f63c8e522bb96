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

// GL chips: the vendor-neutral counts (each compiler reports some of them; "-" where it does not).
std::string neutral_row(const std::string& variant, const std::string& what, const ShaderStats& s, const std::string& est) {
  return fmt::format("{:<44} {:<6} {:>6} {:>5} {:>5} {:>5} {:>5} {:>5} {:>6} {:>7} {:>5} {:>7}\n", variant, what,
                     num(s.instructions), num(s.alu), num(s.texture), num(s.memory), num(s.registers),
                     num(s.occupancy), num(s.spills), num(s.cycles), num(s.loops), est);
}

std::string family_text(const FamilyStats& f, const VariantCosts* costs) {
  std::string out = fmt::format("{}: {} ({}{})\n", f.family, f.device.empty() ? "no device" : f.device,
                                f.driver.empty() ? "driver unknown" : f.driver,
                                f.cached ? fmt::format(", {} of {} pipelines cached", f.cached, f.pipelines.size()) : "");
  const bool amd = f.compiler == "radv";
  if (!f.variants.empty()) {
    const table::GpuCost* first = f.variants.empty() ? nullptr : cost_of(costs, f.variants[0].key, f.family);
    if (first && !first->product.empty())
      out += fmt::format("est_ms: roofline on {} at {}, {} (docs/gpu-cost.md)\n", first->product, first->frame,
                         amd ? "G-buffer excluded" : "G-buffer's render-target write included");
    if (amd)
      out += fmt::format("{:<44} {:<6} {:>5} {:>5} {:>6} {:>5} {:>6} {:>7} {:>5} {:>8} {:>7} {:>6} {:>7}\n", "variant",
                         "pass", "VGPR", "SGPR", "spills", "waves", "instr", "shipped", "VMEM", "latency", "inv.thr",
                         "code", "est_ms");
    else
      out += fmt::format("{:<44} {:<6} {:>6} {:>5} {:>5} {:>5} {:>5} {:>5} {:>6} {:>7} {:>5} {:>7}\n", "variant", "pass",
                         "instr", "alu", "tex", "mem", "regs", "occ", "spills", "cycles", "loops", "est_ms");
    for (const VariantStats& v : f.variants) {
      const table::GpuCost* c = cost_of(costs, v.key, f.family);
      const table::GpuPassCost* ao_cost = c ? c->pass("ao") : nullptr;
      const std::string ao_est = ms(ao_cost ? ao_cost->est_ms : NAN), est = ms(c ? c->est_ms : NAN);
      const PassStats* ao = v.pass("ao");
      if (ao && amd) out += row(v.key, "ao", ao->unrolled(), ao->shipped().instructions, ao_est);
      if (ao && !amd) out += neutral_row(v.key, "ao", ao->unrolled(), ao_est);
      const std::string name = ao ? "" : v.key;
      out += amd ? row(name, "total", v.total(true), v.total(false).instructions, est)
                 : neutral_row(name, "total", v.total(true), est);
    }
  }
  if (!f.error.empty()) out += fmt::format("{}: FAILED: {} ({} variants complete)\n", f.family, f.error, f.variants.size());
  for (const std::string& e : f.program_errors) out += fmt::format("{}: FAILED: {}\n", f.family, e);
  return out;
}

nlohmann::json pipeline_json(const PipelineStats& p, int id) {
  nlohmann::json j = {{"id", id},
                      {"vertex", p.vertex},
                      {"fragment", p.fragment},
                      {"loops_unrolled", p.loops_unrolled},
                      {"neutral", neutral_json(p.unrolled)},
                      {"unrolled", to_json(p.unrolled)}};
  if (p.loops_kept) j["loops_kept"] = p.loops_kept;
  if (!p.specialised.empty()) j["specialised"] = p.specialised;  // e.g. {"params.radius_px": 3}
  if (!p.shipped.empty()) j["shipped"] = to_json(p.shipped);
  if (!p.unrolled.raw.empty()) j["raw"] = p.unrolled.raw;
  return j;
}

}  // namespace

std::string to_text(const GpuAnalysis& a, const VariantCosts* costs) {
  std::string out = "fragment-stage statistics, loops unrolled for analysis: AMD from RADV's null device (ACO; "
                    "'shipped' = instructions of the module as shipped; waves = subgroups per SIMD); NVIDIA, Adreno, "
                    "Mali and Intel from Mesa's GL drivers through drm-shim (alu / tex / mem: instruction counts; "
                    "regs: per thread; occ: waves or threads in flight; cycles: the compiler's own estimate); "
                    "total = every pass once (registers and occupancy: the worst pass)\n";
  for (const FamilyStats& f : a.families) out += "\n" + family_text(f, costs);
  int failed = 0;
  for (const FamilyStats& f : a.families) failed += f.ok() ? 0 : 1;
  out += fmt::format("\n{} GPUs ({} failed), {} distinct pipelines per AMD family, {} distinct programs per GL chip, "
                     "{:.1f} s\n", a.families.size(), failed, a.pipelines, a.gl_programs, a.seconds);
  return out;
}

std::string to_json(const GpuAnalysis& a, const VariantCosts* costs) {
  nlohmann::json families = nlohmann::json::array();
  for (const FamilyStats& f : a.families) {
    nlohmann::json pipelines = nlohmann::json::array(), variants = nlohmann::json::array();
    for (std::size_t i = 0; i < f.pipelines.size(); ++i) pipelines.push_back(pipeline_json(*f.pipelines[i], int(i)));
    for (const VariantStats& v : f.variants) {
      nlohmann::json passes = nlohmann::json::array();
      for (const PassStats& p : v.passes) passes.push_back({{"pass", p.pass}, {"pipeline", p.pipeline}});
      const ShaderStats total = v.total(true);
      nlohmann::json entry = {{"key", v.key}, {"passes", passes}, {"total", {{"neutral", neutral_json(total)}}}};
      if (f.compiler == "radv")
        entry["total"].update({{"unrolled", to_json(total)}, {"shipped", to_json(v.total(false))}});
      const table::GpuCost* c = cost_of(costs, v.key, f.family);
      if (c && !c->product.empty()) entry["estimate"] = table::to_json(*c);  // statistics alone are in "pipelines"
      variants.push_back(std::move(entry));
    }
    families.push_back({{"family", f.family},
                        {"compiler", f.compiler},
                        {"device", f.device},
                        {"driver", f.driver},
                        {"error", f.error},
                        {"program_errors", f.program_errors},
                        {"pipelines", pipelines},
                        {"variants", variants}});
  }
  nlohmann::json j{{"schema_version", util::kSchemaVersion},
                   {"source", "fragment executables: RADV's null device (VK_KHR_pipeline_executable_properties) for "
                              "AMD, Mesa's GL drivers through drm-shim (KHR_debug) for the other chips"},
                   {"pipelines", a.pipelines},
                   {"gl_programs", a.gl_programs},
                   {"families", families}};
  if (costs && !costs->empty() && !costs->begin()->second.empty())  // one frame for the whole run
    j["frame"] = costs->begin()->second.begin()->second.frame;
  return j.dump(1) + "\n";
}

}  // namespace aovar::gpu
