#pragma once
// AMD ISA statistics of a variant's passes per GPU family (issue 17, item 1): every pass's pipeline is
// compiled on RADV's null device of each family (gpu/null_device.h), once with every loop marked Unroll
// (gpu/spirv_unroll.h: what the taps cost) and once as shipped. Each family runs in a child process
// (util::run_isolated), so a compiler crash costs that family, not the run.
#include <filesystem>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "gpu/stats.h"

namespace aovar::gpu {

struct PassStats {
  std::string pass;               // manifest pass ("ao", "blur", ...)
  std::string vertex, fragment;   // program keys
  int loops_unrolled = 0;         // loops the analysis copy marked Unroll (0: unrolled == shipped)
  ShaderStats unrolled, shipped;  // the fragment executable
};

struct VariantStats {
  std::string key;
  std::vector<PassStats> passes;  // in draw order, each pass once (the separable blur's two draws: once)
  const PassStats* pass(const std::string& name) const;  // nullptr when the variant does not run it
  ShaderStats total(bool unrolled) const;                // gpu::combine over its passes
};

struct FamilyStats {
  std::string family;
  std::string device, driver;       // "AMD RADV NAVI21", "Mesa 22.3.6" (empty when the child failed first)
  std::string error;                // one line when the family failed (a crash: the signal); else empty
  std::vector<VariantStats> variants;  // complete variants only, in the order asked
  bool ok() const { return error.empty(); }
};

struct GpuAnalysis {
  std::vector<FamilyStats> families;  // in the order asked
  int pipelines = 0;                  // distinct pipelines compiled per family
  double seconds = 0;
};

struct GpuOptions {
  std::vector<std::string> families;
  std::filesystem::path icd;  // empty: find_radeon_icd()
};

// `variants` index compiled.space.variants; `compiled` holds successful vulkan builds for them. Throws
// std::runtime_error for a missing driver or an unknown family (one line, before any work).
GpuAnalysis analyze_gpu(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                        const GpuOptions& options);

}  // namespace aovar::gpu
