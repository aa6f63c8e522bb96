#pragma once
// Runs a Mesa GL driver's compiler for one chip over many programs (gpu/gl/vendor.h): aovar execs its runner
// (src/gpu/gl/runner, `aovar-gl-stats`) with the vendor's drm-shim preloaded, since LD_PRELOAD cannot reach
// a forked child; one process compiles a whole batch, because start-up (the driver, and under qemu-user the
// emulator) is most of what one compile costs. A driver that crashes costs the program it crashed on: the
// runner is started again after it.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gpu/gl/vendor.h"
#include "gpu/stats.h"

namespace aovar::gpu {

// What scripts/mesa-gl and scripts/intel-shim installed, and the runners this aovar was built with.
struct GlInstall {
  std::filesystem::path prefix;        // $AOVAR_MESA_PREFIX, else the pinned /opt/aovar/mesa-25.0.7
  std::filesystem::path runner_amd64;  // aovar-gl-stats
  std::filesystem::path runner_arm64;  // aovar-gl-stats-arm64 (Debian's aarch64 cross compiler)
  std::filesystem::path qemu;          // qemu-aarch64-static
  std::string mesa;                    // "25.0.7-2~bpo12+1": the unpacked packages' version, else empty
};

// Looks everything up; never throws (what is missing is said by check_installed).
GlInstall find_gl_install();

// Throws std::runtime_error, one line, naming what `vendor` lacks and the script that installs it.
void check_installed(const GlInstall& install, const GlVendor& vendor);

struct GlProgram {
  std::string name;              // for messages: "alchemy-s08-...-hp.frag"
  std::string vertex, fragment;  // GLSL ES sources
};

struct GlResult {
  std::optional<ShaderStats> stats;  // the fragment program's statistics
  std::string error;                 // one line when the driver rejected it, crashed on it or said nothing
};

struct GlBatch {
  std::string renderer, version;  // GL_RENDERER ("NVC8"), GL_VERSION ("OpenGL ES 3.1 Mesa 25.0.7-...")
  std::vector<GlResult> results;  // one per program, in order
};

// Compiles every program on the chip `chip_value` of `vendor` (the value of its chip variable). Throws
// std::runtime_error when the runner cannot start at all (the missing piece, or its last words).
GlBatch compile_on_chip(const GlInstall& install, const GlVendor& vendor, const std::string& chip_value,
                        const std::vector<GlProgram>& programs);

}  // namespace aovar::gpu
