#include "gpu/by_key.h"

#include <stdexcept>

#include "compile/generate.h"
#include "gpu/costs.h"
#include "gpu/families.h"
#include "gpu/family_specs.h"
#include "gpu/gl/compiler.h"

namespace aovar::gpu {

namespace {

bool any_amd(const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (!gl_chip(n)) return true;
  return false;
}

}  // namespace

void check_gpus(const std::vector<std::string>& names) {
  std::vector<std::string> amd;
  const GlInstall install = find_gl_install();
  for (const std::string& name : names) {
    if (const FamilySpec* chip = gl_chip(name)) check_installed(install, *gl_vendor(chip->compiler->driver));
    else amd.push_back(name);
  }
  if (!amd.empty()) check_families(find_radeon_icd(), amd);
}

KeyedCosts costs_by_key(const CostRequest& request, const std::set<std::string>& keys) {
  KeyedCosts out;
  if (request.families.empty() || keys.empty()) return out;
  compile::CompileOptions co{request.scope};
  co.scope.targets = {variants::Target::vulkan};  // the plans and loads read the Vulkan builds
  for (const std::string& name : request.families)
    if (gl_chip(name)) {
      co.scope.targets.push_back(variants::Target::gles30);  // a GL chip compiles the gles30 programs
      break;
    }
  co.globs.assign(keys.begin(), keys.end());  // an exact key is a glob matching itself
  const auto compiled = compile::compile_space(co);
  // The caller measured these variants: a failure here is not a template error but a broken cache or manifest.
  if (!compiled.ok())
    throw std::runtime_error("--gpu: compiling the variants failed: " +
                             (compiled.diagnostics.empty() ? std::string("no diagnostics") : compiled.diagnostics.front()));
  std::vector<int> selected;
  for (std::size_t v = 0; v < compiled.space.variants.size(); ++v)
    if (keys.count(compiled.space.variants[v].key)) selected.push_back(static_cast<int>(v));
  GpuOptions options;
  options.families = request.families;
  options.scope = request.scope;
  options.calibration = request.calibration;
  if (any_amd(request.families)) options.icd = find_radeon_icd();
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
