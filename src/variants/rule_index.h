#pragma once
// Which rules drop each point of the variant space, for build_space's walk over the whole product. Testing
// every rule at every point costs points x rules (50,000 rules over the default 40,320 points took a
// minute); here each rule is one bit, each axis value holds the bits of the rules it satisfies, and the walk
// keeps the AND over the axes it has fixed, so a point costs a few word operations per 64 rules.
#include <cstdint>
#include <vector>

#include "variants/manifest.h"

namespace aovar::variants {

class RuleWalk {
 public:
  explicit RuleWalk(const Manifest& m);
  // Moves to point p, of which axes first_changed.. differ from the previous point (0 for the first).
  void move_to(const Point& p, int first_changed);
  // The first rule (in manifest order) that drops the current point, or -1.
  int first_drop() const;
  // Whether a rule dropped any point visited so far: a rule that drops none is a mistake in the manifest.
  bool ever_dropped(std::size_t rule) const { return ever_[rule / 64] >> (rule % 64) & 1u; }

 private:
  using Bits = std::vector<std::uint64_t>;
  std::size_t words_ = 0;
  // Per axis and value: the rules whose `when` (skip: `match`) accepts it, and the `only` rules whose
  // `match` accepts it (a skip rule's bit is never set there: nothing keeps what it matches).
  std::vector<std::vector<Bits>> when_, keep_;
  // The ANDs over axes 0..a of the current point (a = kAxisCount - 1: the whole point).
  std::vector<Bits> when_prefix_, keep_prefix_;
  Bits drop_, ever_;
};

}  // namespace aovar::variants
