#pragma once
// Compiler statistics of variants on the chips Mesa's GL drivers compile for (NVIDIA, Adreno, Mali, Intel:
// families.json's products with a "compiler"). Per variant, each pass's gles30 vertex + fragment program is
// preprocessed and its loops unrolled (gpu/gl/unroll.h) once, then compiled per chip in one batch
// (gpu/gl/compiler.h). Results are cached per program pair, chip and Mesa version in the verified cache layer
// (CACHE/gl-stats, util/verified_cache.h: its full key and a checksum), and the vendor's parser must read an
// entry before it is used; anything else is compiled again with a warning. A loop whose bound is computed from
// a parameter (the blurs' radius) is unrolled at the value the variant renders with (gpu/gl/unroll.h), so its
// statistics count the real trip count, and the cache keeps one entry per value.
#include <filesystem>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "gpu/gl/unroll.h"
#include "gpu/gpu.h"
#include "variants/manifest.h"

namespace aovar::gpu {

struct GlChipsAnalysis {
  std::vector<FamilyStats> chips;  // in the order asked
  int programs = 0;                // distinct vertex + fragment pairs
};

// Throws std::runtime_error, one line, before compiling anything: a name that is no GL chip, or a vendor whose
// driver, shim, runner or emulator is missing (naming the script that installs it). A chip whose runner then
// fails has its FamilyStats::error; a program its driver rejects or crashes on, a line in program_errors.
// `compiled` must hold the gles30 builds of `variants`. `cache_dir` empty: no cache. `calibration`: the
// parameter values the variants render with (by variant key or algorithm, compile::calibrated_for); a
// parameter it does not name takes the manifest's value.
GlChipsAnalysis analyze_gl_chips(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                                 const std::vector<std::string>& chips, const std::filesystem::path& cache_dir,
                                 const variants::CalibratedValues& calibration = {});

// The cache key of one program pair on one chip (exposed for the cache's tests): the unrolled sources and the
// parameter values their loop bounds were specialised on (GlslUnroll::specialised).
std::string gl_cache_key(const std::string& chip, const std::string& driver_chip, const std::string& mesa,
                         const std::string& vertex, const std::string& fragment, const GlslInputs& specialised = {});

}  // namespace aovar::gpu
