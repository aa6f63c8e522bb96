#pragma once
// What a SPIR-V module executes, as a hash: two programs with the same fingerprint run the same instructions
// on a driver that ignores the given decorations (llvmpipe ignores RelaxedPrecision, so a mediump program and
// its highp twin run the same fp32 code there: measure/same_code.h).
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace aovar::compile {

// The SPIR-V Decoration numbers (spv::Decoration) a driver is known to ignore.
using Decorations = std::set<std::uint32_t>;
Decorations relaxed_precision_only();  // {RelaxedPrecision}

// A hash of `spirv` without the instructions that cannot change execution (OpSource*, OpName, OpMemberName,
// OpString, OpLine, OpNoLine, OpModuleProcessed) and without the OpDecorate / OpMemberDecorate whose
// decoration is in `ignored`. Empty for an empty module (gles30 has no SPIR-V: callers fall back to the
// program's key). Throws std::runtime_error for a malformed module.
std::string executable_fingerprint(const std::vector<std::uint32_t>& spirv, const Decorations& ignored);

}  // namespace aovar::compile
