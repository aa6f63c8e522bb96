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
  // Throws std::invalid_argument unless line_bytes is a power of two and size_bytes a whole number of
  // sets of `ways` lines.
  SetAssocCache(int64_t size_bytes, int line_bytes, int ways) : ways_(ways) {
    if (line_bytes < 1 || (line_bytes & (line_bytes - 1)) != 0 || ways < 1 || size_bytes < int64_t(line_bytes) * ways ||
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
  // evicts the least recently used. Sets are line mod sets (no hashing), which the tests rely on.
  bool access(uint64_t line) {
    const uint64_t set = pow2_ ? line & set_mask_ : line % sets_;
    uint64_t* ways = tags_.data() + set * uint64_t(ways_);  // most recently used first
    // One pass finds the line and moves it to the front: each way takes the one before it until the
    // line's old place (a hit) or the end (a miss: the least recently used falls out).
    uint64_t carried = line;
    for (int i = 0; i < ways_; ++i) {
      const uint64_t here = ways[i];
      ways[i] = carried;
      if (here == line) return true;
      carried = here;
    }
    return false;
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  int ways_ = 1;
  int line_shift_ = 0;
  uint64_t sets_ = 1, set_mask_ = 0;
  bool pow2_ = true;
  std::vector<uint64_t> tags_;  // sets x ways
};

}  // namespace aovar::gpu
