#include "gpu/spirv_unroll.h"

#include <stdexcept>

namespace aovar::gpu {
namespace {
constexpr std::uint32_t kMagic = 0x07230203;
constexpr std::size_t kHeaderWords = 5;
constexpr std::uint32_t kOpLoopMerge = 246;  // OpLoopMerge %merge %continue LoopControl [operands]
constexpr std::uint32_t kUnroll = 0x1, kDontUnroll = 0x2;
}  // namespace

UnrollRewrite with_unroll_hints(const std::vector<std::uint32_t>& spirv) {
  if (spirv.size() < kHeaderWords || spirv[0] != kMagic)
    throw std::runtime_error("gpu: not a SPIR-V module (bad magic or too short); regenerate the variant's SPIR-V");
  UnrollRewrite out{spirv, 0};
  std::size_t i = kHeaderWords;
  while (i < out.words.size()) {
    const std::uint32_t count = out.words[i] >> 16, opcode = out.words[i] & 0xffff;
    if (count == 0 || i + count > out.words.size())
      throw std::runtime_error("gpu: malformed SPIR-V (instruction runs past the end); regenerate the variant's SPIR-V");
    if (opcode == kOpLoopMerge && count >= 4) {
      std::uint32_t& control = out.words[i + 3];
      const std::uint32_t wanted = (control | kUnroll) & ~kDontUnroll;
      if (wanted != control) {
        control = wanted;
        ++out.loops_changed;
      }
    }
    i += count;
  }
  return out;
}

}  // namespace aovar::gpu
