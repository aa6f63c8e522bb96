#pragma once
// Compiler statistics of variants on the chips Mesa's GL drivers compile for (NVIDIA, Adreno, Mali, Intel:
// families.json's products with a "compiler"). Per variant, each pass's gles30 vertex + fragment program is
// preprocessed and its loops unrolled (gpu/gl/unroll.h) once, then compiled per chip in one batch
// (gpu/gl/compiler.h). Results are cached per program pair, chip and Mesa version in the verified cache layer
// (CACHE/gl-stats, util/verified_cache.h: its full key and a checksum), and the vendor's parser must read an
// entry before it is used; anything else is compiled again with a warning.
#include <filesystem>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "gpu/gpu.h"

namespace aovar::gpu {

struct GlChipsAnalysis {
  std::vector<FamilyStats> chips;  // in the order asked
  int programs = 0;                // distinct vertex + fragment pairs
};

// Throws std::runtime_error, one line, before compiling anything: a name that is no GL chip, or a vendor whose
// driver, shim, runner or emulator is missing (naming the script that installs it). A chip whose runner then
// fails has its FamilyStats::error; a program its driver rejects or crashes on, a line in program_errors.
// `compiled` must hold the gles30 builds of `variants`. `cache_dir` empty: no cache.
GlChipsAnalysis analyze_gl_chips(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                                 const std::vector<std::string>& chips, const std::filesystem::path& cache_dir);

// The cache key of one program pair on one chip (exposed for the cache's tests).
std::string gl_cache_key(const std::string& chip, const std::string& driver_chip, const std::string& mesa,
                         const std::string& vertex, const std::string& fragment);

}  // namespace aovar::gpu
