// The bit-parallel rule walk build_space uses (variants/rule_index.h, issue 34 point 5) decides exactly
// what testing every rule at every point decides: the first rule that drops a point, and which rules drop
// any point at all; on the default manifest and on thousands of random rules.
#include <gtest/gtest.h>

#include <random>

#include "test_support.h"
#include "variants/manifest.h"
#include "variants/rule_index.h"
#include "variants/space.h"

namespace {
using namespace aovar::variants;

Manifest default_manifest() { return load_manifest(aovar::test::source_dir() / "shader_src/aovar.toml"); }

bool drops(const Rule& r, const Point& p) {
  return r.kind == Rule::Kind::skip ? r.match.matches(p) : (r.when.matches(p) && !r.match.matches(p));
}

// A predicate constraining about `axes` random axes to random non-empty value subsets.
Predicate random_predicate(const Manifest& m, std::mt19937& gen, int axes) {
  Predicate p;
  for (int i = 0; i < axes; ++i) {
    const int a = static_cast<int>(gen() % kAxisCount);
    const int values = static_cast<int>(m.values[a].size());
    std::uint64_t bits = 0;
    while (!bits) bits = gen() & ((std::uint64_t{1} << values) - 1);
    p.allowed[a] = bits;
  }
  return p;
}

// Walks the whole product both ways; returns the points compared.
std::uint64_t compare_walks(const Manifest& m) {
  std::array<int, kAxisCount> sizes{};
  std::uint64_t space = 1;
  for (int a = 0; a < kAxisCount; ++a) space *= sizes[a] = static_cast<int>(m.values[a].size());
  RuleWalk walk(m);
  std::vector<bool> ever(m.rules.size(), false);
  Point p{};
  for (std::uint64_t n = 0; n < space; ++n) {
    int first_changed = 0;
    if (n > 0) {
      int a = kAxisCount - 1;
      while (++p[a] == sizes[a]) p[a--] = 0;
      first_changed = a;
    }
    walk.move_to(p, first_changed);
    int first = -1;
    for (std::size_t r = 0; r < m.rules.size(); ++r)
      if (drops(m.rules[r], p)) {
        ever[r] = true;
        if (first < 0) first = static_cast<int>(r);
      }
    EXPECT_EQ(walk.first_drop(), first) << "point " << n;
    if (walk.first_drop() != first) return n;
  }
  for (std::size_t r = 0; r < m.rules.size(); ++r) EXPECT_EQ(walk.ever_dropped(r), ever[r]) << "rule " << r;
  return space;
}

TEST(RuleWalk, AgreesWithTestingEveryRuleOnTheDefaultManifest) {
  const Manifest m = default_manifest();
  EXPECT_EQ(compare_walks(m), build_space(m).space);
}

TEST(RuleWalk, AgreesOnRandomSkipAndOnlyRulesAcrossWordBoundaries) {
  std::mt19937 gen(34);
  Manifest m = default_manifest();
  m.rules.clear();
  for (int i = 0; i < 200; ++i) {  // more than three 64-bit words of rules, some that match nothing
    Rule r;
    r.kind = gen() % 3 == 0 ? Rule::Kind::only : Rule::Kind::skip;
    if (r.kind == Rule::Kind::only) r.when = random_predicate(m, gen, 1 + static_cast<int>(gen() % 2));
    r.match = random_predicate(m, gen, 2 + static_cast<int>(gen() % 4));
    m.rules.push_back(r);
  }
  compare_walks(m);
}

TEST(RuleWalk, BuildSpaceCountsWithManyRules) {
  // 5,000 random skip rules on the default manifest: the counts add up, each rule drops what the naive test
  // says it drops first.
  std::mt19937 gen(7);
  Manifest m = default_manifest();
  const std::size_t own = m.rules.size();
  for (int i = 0; i < 5000; ++i) {
    Rule r;
    r.match = random_predicate(m, gen, 4);
    m.rules.push_back(r);
  }
  const VariantSpace s = build_space(m);
  std::vector<std::uint64_t> expected(m.rules.size(), 0);
  std::uint64_t kept = 0;
  std::array<int, kAxisCount> sizes{};
  for (int a = 0; a < kAxisCount; ++a) sizes[a] = static_cast<int>(m.values[a].size());
  Point p{};
  for (std::uint64_t n = 0; n < s.space; ++n) {
    std::uint64_t rest = n;
    for (int a = kAxisCount - 1; a >= 0; --a) {
      p[a] = static_cast<int>(rest % sizes[a]);
      rest /= sizes[a];
    }
    std::size_t r = 0;
    while (r < m.rules.size() && !drops(m.rules[r], p)) ++r;
    if (r < m.rules.size()) ++expected[r];
    else ++kept;
  }
  EXPECT_EQ(s.rule_drops, expected);
  EXPECT_EQ(s.after_rules, kept);
  EXPECT_GT(own, 0u);
}

}  // namespace
