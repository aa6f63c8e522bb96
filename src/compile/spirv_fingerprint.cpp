#include "compile/spirv_fingerprint.h"

#include <stdexcept>
#include <string_view>

// glslang's copy of the Khronos header (Debian's spirv-headers package is not a dependency; glslang is).
#include <glslang/SPIRV/spirv.hpp>

#include "util/hash.h"

// The words are walked here rather than through a SPIRV-Tools pass (strip-debug plus a decoration filter):
// a hash needs no rewritten, re-validated module, and dropping words keeps every result id as it is, so two
// modules that differ only in what is dropped hash equal.
namespace aovar::compile {
namespace {
constexpr std::size_t kHeaderWords = 5;  // magic, version, generator, id bound, schema

bool is_debug(std::uint32_t op) {
  switch (op) {
    case spv::OpSource: case spv::OpSourceContinued: case spv::OpSourceExtension: case spv::OpName:
    case spv::OpMemberName: case spv::OpString: case spv::OpLine: case spv::OpNoLine: case spv::OpModuleProcessed:
      return true;
    default:
      return false;
  }
}

// OpDecorate %target Decoration ...; OpMemberDecorate %struct member Decoration ...
bool is_ignored_decoration(const std::uint32_t* ins, std::uint32_t count, const Decorations& ignored) {
  const std::uint32_t op = ins[0] & 0xffff;
  if (op == spv::OpDecorate && count >= 3) return ignored.count(ins[2]) > 0;
  if (op == spv::OpMemberDecorate && count >= 4) return ignored.count(ins[3]) > 0;
  return false;
}
}  // namespace

Decorations relaxed_precision_only() { return {spv::DecorationRelaxedPrecision}; }

std::string executable_fingerprint(const std::vector<std::uint32_t>& spirv, const Decorations& ignored) {
  if (spirv.empty()) return {};
  if (spirv.size() < kHeaderWords || spirv[0] != spv::MagicNumber)
    throw std::runtime_error("spirv fingerprint: not a SPIR-V module (bad magic or too short)");
  util::Hasher h;
  // The header minus the generator word (a tool's id cannot change execution).
  h.add(spirv[1]).add(spirv[3]).add(spirv[4]);
  for (std::size_t i = kHeaderWords; i < spirv.size();) {
    const std::uint32_t count = spirv[i] >> 16;
    if (count == 0 || i + count > spirv.size())
      throw std::runtime_error("spirv fingerprint: malformed SPIR-V (an instruction runs past the end)");
    if (!is_debug(spirv[i] & 0xffff) && !is_ignored_decoration(&spirv[i], count, ignored))
      h.add(std::string_view(reinterpret_cast<const char*>(&spirv[i]), count * sizeof(std::uint32_t)));
    i += count;
  }
  return h.hex();
}

}  // namespace aovar::compile
