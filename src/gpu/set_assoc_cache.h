#pragma once
// One set-associative cache with least-recently-used replacement, for the cache simulator
// (gpu/cache_sim.h): tags only, no data. Inline: it is the simulator's inner loop.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace aovar::gpu {

class SetAssocCache {
 public:
  // Throws std::invalid_argument unless line_bytes is a power of two of at least 4 and size_bytes a whole
  // number of sets of `ways` lines.
  SetAssocCache(int64_t size_bytes, int line_bytes, int ways) : ways_(ways) {
    if (line_bytes < 4 || (line_bytes & (line_bytes - 1)) != 0 || ways < 1 || size_bytes < int64_t(line_bytes) * ways ||
        size_bytes % (int64_t(line_bytes) * ways) != 0)
      throw std::invalid_argument("cache of " + std::to_string(size_bytes) + " bytes, " + std::to_string(line_bytes) +
                                  "-byte lines, " + std::to_string(ways) + " ways: not a whole number of sets");
    while ((1 << line_shift_) < line_bytes) ++line_shift_;
    sets_ = uint64_t(size_bytes / (int64_t(line_bytes) * ways));
    pow2_ = (sets_ & (sets_ - 1)) == 0;
    set_mask_ = sets_ - 1;
    tags_.assign(sets_ * uint64_t(ways), kEmpty);
  }

  // The line holding byte `address`.
  uint64_t line_of(uint64_t address) const { return address >> line_shift_; }
  int line_shift() const { return line_shift_; }
  uint64_t sets() const { return sets_; }

  // Looks `line` up: true on a hit. Either way the line becomes its set's most recently used; a miss
  // evicts the least recently used. Sets are line mod sets (no hashing), which the tests rely on. Line
  // numbers must be below 2^32 - 1 (see tags_).
  bool access(uint64_t line64) {
    const uint32_t line = uint32_t(line64);  // see tags_
    const uint64_t set = pow2_ ? line64 & set_mask_ : line64 % sets_;
    const int n = ways_;  // a local: the stores below may alias the member
    uint32_t* ways = tags_.data() + set * uint64_t(n);  // most recently used first
    // One pass finds the line and moves it to the front: each way takes the one before it until the
    // line's old place (a hit) or the end (a miss: the least recently used falls out).
    uint32_t carried = line;
    for (int i = 0; i < n; ++i) {
      const uint32_t here = ways[i];
      ways[i] = carried;
      if (here == line) return true;
      carried = here;
    }
    return false;
  }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t(0);
  int ways_ = 1;
  int line_shift_ = 0;
  uint64_t sets_ = 1, set_mask_ = 0;
  bool pow2_ = true;
  // sets x ways. 32-bit line numbers halve the simulator's memory traffic: a trace's textures span at most
  // 7 slots x 8192^2 texels x 16 bytes x 4/3 (MIP levels) < 11 GB, under 2^32 lines of 4 bytes or more.
  std::vector<uint32_t> tags_;
};

}  // namespace aovar::gpu
