#pragma once
// GPU compiler statistics of a variant's passes per chip. AMD families: every pass's pipeline compiled on
// RADV's null device of each family (gpu/null_device.h), once with every loop marked Unroll
// (gpu/spirv_unroll.h: what the taps cost) and once as shipped, each family in a child process
// (util::run_isolated), so a compiler crash costs that family, not the run. NVIDIA, Adreno, Mali and Intel
// chips: the gles30 programs, loops unrolled in source (gpu/gl/unroll.h), compiled by Mesa's GL driver for
// the chip through its drm-shim (gpu/gl/analysis.h).
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "gpu/stats.h"
#include "variants/manifest.h"

namespace aovar::gpu {

// One distinct pipeline's fragment statistics, shared by every variant that draws the same programs into
// the same formats: held once however many variants use it.
struct PipelineStats {
  std::string vertex, fragment;   // program keys
  int loops_unrolled = 0;         // loops the analysis copy unrolled (0: unrolled == shipped)
  int loops_kept = 0;             // loops the analysis copy left rolled (GL chips): bounds it cannot evaluate
  ShaderStats unrolled, shipped;  // the fragment executable; `shipped` empty where only the analysis copy ran
  std::map<std::string, double> specialised;  // GL chips: parameter values its loop bounds were unrolled at
};

struct PassStats {
  std::string pass;                              // manifest pass ("ao", "blur", ...)
  int pipeline = -1;                             // index into FamilyStats::pipelines
  std::shared_ptr<const PipelineStats> stats;    // that pipeline
  const ShaderStats& unrolled() const { return stats->unrolled; }
  const ShaderStats& shipped() const { return stats->shipped; }
};

struct VariantStats {
  std::string key;
  std::vector<PassStats> passes;  // in draw order, each pass once (the separable blur's two draws: once)
  const PassStats* pass(const std::string& name) const;  // nullptr when the variant does not run it
  ShaderStats total(bool unrolled) const;                // gpu::combine over its passes
};

// One chip's statistics: an AMD family on RADV's null device, or a GL chip through its drm-shim.
struct FamilyStats {
  std::string family;               // "navi21", "gf110", "a320"
  std::string device, driver;       // "AMD RADV NAVI21" / "FD320", "Mesa 25.0.7" (empty when it failed first)
  std::string compiler;             // "radv", or the GL vendor ("nouveau", "freedreno", ...)
  std::string error;                // one line when the chip failed (a crash: the signal); else empty
  std::vector<std::string> program_errors;  // one line per program the driver rejected or crashed on
  std::vector<std::shared_ptr<const PipelineStats>> pipelines;  // each distinct pipeline once
  std::vector<VariantStats> variants;  // complete variants only, in the order asked
  int cached = 0;                      // pipelines read from the statistics cache (GL chips)
  bool ok() const { return error.empty() && program_errors.empty(); }
};

struct GpuAnalysis {
  std::vector<FamilyStats> families;  // in the order asked
  int pipelines = 0;                  // distinct pipelines per AMD family (Vulkan plans)
  int gl_programs = 0;                // distinct vertex + fragment programs per GL chip
  double seconds = 0;
};

struct GpuOptions {
  std::vector<std::string> families;  // AMD families (RADV names) and GL chips (gpu/family_specs.h gl_chips)
  std::filesystem::path icd;          // empty: find_radeon_icd(), when an AMD family is asked for
  compile::RunScope scope;            // its cache root holds the GL chips' statistics cache (empty: none)
  // The parameter values the variants render with (by variant key or algorithm; the rest: the manifest's).
  // GL chips unroll a loop bounded by a parameter (the blurs' radius) at its value; AMD families do not.
  variants::CalibratedValues calibration;
};

// `variants` index compiled.space.variants; `compiled` holds successful vulkan builds for them (AMD families)
// and gles30 builds (GL chips). Throws std::runtime_error for a missing driver or an unknown chip (one line,
// before any work).
GpuAnalysis analyze_gpu(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                        const GpuOptions& options);

}  // namespace aovar::gpu
