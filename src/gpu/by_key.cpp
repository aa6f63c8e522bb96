#include "gpu/by_key.h"

#include <stdexcept>

#include "compile/generate.h"
#include "gpu/costs.h"
#include "gpu/families.h"

namespace aovar::gpu {

void check_request(const CostRequest& request) {
  if (request.families.empty()) return;
  check_families(find_radeon_icd(), request.families);
}

KeyedCosts costs_by_key(const CostRequest& request, const std::set<std::string>& keys) {
  KeyedCosts out;
  if (request.families.empty() || keys.empty()) return out;
  compile::CompileOptions co;
  co.targets = {variants::Target::vulkan};
  co.globs.assign(keys.begin(), keys.end());  // an exact key is a glob matching itself
  co.cache_dir = request.cache_dir;
  co.jobs = request.jobs;
  const auto compiled = compile::compile_space(request.manifest, co);
  // The caller measured these variants: a failure here is not a template error but a broken cache or manifest.
  if (!compiled.ok())
    throw std::runtime_error("--gpu: compiling the variants failed: " +
                             (compiled.diagnostics.empty() ? std::string("no diagnostics") : compiled.diagnostics.front()));
  std::vector<int> selected;
  for (std::size_t v = 0; v < compiled.space.variants.size(); ++v)
    if (keys.count(compiled.space.variants[v].key)) selected.push_back(static_cast<int>(v));
  GpuOptions options;
  options.families = request.families;
  options.icd = find_radeon_icd();
  const GpuAnalysis analysis = analyze_gpu(compiled, selected, options);
  out.by_variant = costs_of(analysis, variant_loads(compiled, selected), request.frame,
                            &out.errors);
  for (const auto& f : analysis.families)
    if (out.mesa.empty() && !f.driver.empty()) out.mesa = f.driver;
  out.pipelines = analysis.pipelines;
  out.seconds = analysis.seconds;
  return out;
}

}  // namespace aovar::gpu
