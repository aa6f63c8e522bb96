// aovar analyze --gpu: every pass of the selected variants compiled per chip (RADV's null device for AMD
// families, Mesa's GL drivers through drm-shim for NVIDIA, Adreno, Mali and Intel chips), the compilers'
// statistics and, where a product has one, the roofline estimate -> text and gpu.json (docs/gpu-cost.md).
#include <fmt/format.h>

#include <iostream>

#include "cli/render_options.h"
#include "cli/render_parts.h"
#include "gpu/costs.h"
#include "gpu/families.h"
#include "gpu/family_specs.h"
#include "gpu/gpu.h"
#include "gpu/text.h"
#include "util/fs.h"

namespace aovar::cli {

ExitCode run_analyze_gpu(const GpuAnalyzeArgs& a) {
  const gpu::Frame frame = parse_size(a.size);
  const auto lock = lock_output(a.out);
  gpu::GpuOptions options;
  options.families = gpu::parse_families(a.families);
  options.scope = a.common.scope();
  bool amd = false, gl = false;
  for (const std::string& name : options.families) (gpu::gl_chip(name) ? gl : amd) = true;
  if (amd) options.icd = gpu::find_radeon_icd();  // before compiling: a missing driver is the first thing to say
  compile::CompileOptions co = compile_options(a.common);
  co.scope.targets = {variants::Target::vulkan};  // the plans (and the AMD pipelines) read the Vulkan builds
  if (gl) co.scope.targets.push_back(variants::Target::gles30);
  const auto compiled = compile::compile_space(co);
  if (!report_diagnostics(compiled)) return ExitCode::error;  // the diagnostics are printed
  std::vector<int> variants(compiled.space.variants.size());
  for (std::size_t i = 0; i < variants.size(); ++i) variants[i] = static_cast<int>(i);
  const gpu::GpuAnalysis result = gpu::analyze_gpu(compiled, variants, options);
  const gpu::VariantCosts costs = gpu::costs_of(result, gpu::variant_loads(compiled, variants), frame);
  std::cout << gpu::to_text(result, &costs);
  if (!a.out.empty()) {
    const auto path = std::filesystem::path(a.out) / "gpu.json";
    std::filesystem::create_directories(a.out);
    util::write_atomic(path, gpu::to_json(result, &costs));
    std::cout << fmt::format("wrote {}\n", path.string());
  }
  for (const auto& f : result.families)
    if (!f.ok()) return ExitCode::error;
  return ExitCode::ok;
}

}  // namespace aovar::cli
