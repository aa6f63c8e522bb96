// Bit-parallel rule matching for the walk over the variant space (rule_index.h).
#include "variants/rule_index.h"

#include <bit>

namespace aovar::variants {
namespace {

bool accepts(const Predicate& p, int axis, int value) {
  return p.allowed[axis] == 0 || (p.allowed[axis] >> value & 1u);
}

}  // namespace

RuleWalk::RuleWalk(const Manifest& m) : words_((m.rules.size() + 63) / 64) {
  when_.resize(kAxisCount);
  keep_.resize(kAxisCount);
  for (int a = 0; a < kAxisCount; ++a) {
    const int values = static_cast<int>(m.values[a].size());
    when_[a].assign(values, Bits(words_, 0));
    keep_[a].assign(values, Bits(words_, 0));
    for (std::size_t r = 0; r < m.rules.size(); ++r) {
      const Rule& rule = m.rules[r];
      const bool skip = rule.kind == Rule::Kind::skip;
      const std::uint64_t bit = std::uint64_t{1} << (r % 64);
      for (int v = 0; v < values; ++v) {
        if (accepts(skip ? rule.match : rule.when, a, v)) when_[a][v][r / 64] |= bit;
        if (!skip && accepts(rule.match, a, v)) keep_[a][v][r / 64] |= bit;
      }
    }
  }
  when_prefix_.assign(kAxisCount, Bits(words_, 0));
  keep_prefix_.assign(kAxisCount, Bits(words_, 0));
  drop_.assign(words_, 0);
  ever_.assign(words_, 0);
}

void RuleWalk::move_to(const Point& p, int first_changed) {
  for (int a = first_changed; a < kAxisCount; ++a) {
    const Bits& w = when_[a][p[a]];
    const Bits& k = keep_[a][p[a]];
    Bits& wp = when_prefix_[a];
    Bits& kp = keep_prefix_[a];
    if (a == 0) {
      wp = w;
      kp = k;
    } else {
      const Bits& wprev = when_prefix_[a - 1];
      const Bits& kprev = keep_prefix_[a - 1];
      for (std::size_t i = 0; i < words_; ++i) {
        wp[i] = wprev[i] & w[i];
        kp[i] = kprev[i] & k[i];
      }
    }
  }
  // A rule drops the point when its `when` (skip: `match`) holds and, for `only`, its `match` does not.
  const Bits& w = when_prefix_[kAxisCount - 1];
  const Bits& k = keep_prefix_[kAxisCount - 1];
  for (std::size_t i = 0; i < words_; ++i) {
    drop_[i] = w[i] & ~k[i];
    ever_[i] |= drop_[i];
  }
}

int RuleWalk::first_drop() const {
  for (std::size_t i = 0; i < words_; ++i)
    if (drop_[i]) return static_cast<int>(i * 64 + static_cast<std::size_t>(std::countr_zero(drop_[i])));
  return -1;
}

}  // namespace aovar::variants
