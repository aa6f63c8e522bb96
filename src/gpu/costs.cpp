#include "gpu/costs.h"

#include "gpu/family_specs.h"
#include "gpu/pass_loads.h"
#include "render/plan.h"

namespace aovar::gpu {

std::map<std::string, std::vector<PassLoad>> variant_loads(const compile::CompiledSpace& compiled,
                                                           const std::vector<int>& variants,
                                                           std::map<std::string, analyze::ProgramCost>* analysed) {
  std::map<std::string, std::vector<PassLoad>> loads;
  std::map<std::string, analyze::ProgramCost> own;
  for (int v : variants) {
    const render::PipelinePlan plan = render::plan_pipeline(compiled, v, variants::Target::vulkan);
    loads[plan.variant] = pass_loads(plan, analysed ? *analysed : own);
  }
  return loads;
}

std::map<std::string, table::GpuCosts> costs_of(const GpuAnalysis& analysis,
                                                const std::map<std::string, std::vector<PassLoad>>& loads,
                                                Frame frame, std::vector<std::string>* errors) {
  std::map<std::string, table::GpuCosts> out;
  for (const FamilyStats& f : analysis.families) {
    if (!f.ok() && errors) errors->push_back(f.family + ": " + f.error);
    const FamilySpec* spec = estimate_spec(f.family);
    for (const VariantStats& v : f.variants) {
      auto it = loads.find(v.key);
      if (it == loads.end()) continue;
      table::GpuCost& cost = out[v.key][f.family] = estimate(v, it->second, spec, frame, f.driver);
      cost.compiler = f.compiler;
    }
  }
  return out;
}

}  // namespace aovar::gpu
