#pragma once
// mediump as a mobile GPU runs it, on drivers that run it in fp32 (Mesa's CPU drivers): rewrites the arithmetic
// on RelaxedPrecision values (glslang's mediump) of a Vulkan SPIR-V module into real 16-bit float operations
// with SPIRV-Tools' convert-relaxed-to-half pass. Variables, interfaces and image operations stay 32-bit; the
// result declares the Float16 capability, so a Vulkan device must enable shaderFloat16 to accept it.
#include <cstdint>
#include <vector>

namespace aovar::compile {

// True when some OpDecorate / OpMemberDecorate of the module names RelaxedPrecision (word scan, no parsing).
bool has_relaxed_precision(const std::vector<std::uint32_t>& spirv);

// Vulkan 1.2 SPIR-V in, validated Vulkan 1.2 SPIR-V out. A module without RelaxedPrecision comes back as is
// (not validated: nothing was changed). Thread-safe. Throws std::runtime_error ("mediump->fp16: ...") when the
// input has no SPIR-V header or does not validate, a pass fails, or the result does not validate.
std::vector<std::uint32_t> relaxed_precision_to_fp16(const std::vector<std::uint32_t>& spirv);

}  // namespace aovar::compile
