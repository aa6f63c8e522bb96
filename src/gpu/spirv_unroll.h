#pragma once
// A copy of a SPIR-V module with every loop marked Unroll, for analysis only (never shipped): RADV's NIR
// keeps loops of more than ~8 iterations rolled, so s16 and s32 would get the same statistics; with the
// hint, loops with constant trip counts are unrolled and the instruction counts grow with the taps.
#include <cstdint>
#include <vector>

namespace aovar::gpu {

struct UnrollRewrite {
  std::vector<std::uint32_t> words;  // the rewritten module
  int loops_changed = 0;             // OpLoopMerge instructions whose control changed (0: same as the input)
};

// Sets Unroll (0x1) and clears DontUnroll (0x2) in every OpLoopMerge's loop control. Neither bit takes
// operands, so no instruction changes length. Throws std::runtime_error for words that are not SPIR-V.
UnrollRewrite with_unroll_hints(const std::vector<std::uint32_t>& spirv);

}  // namespace aovar::gpu
