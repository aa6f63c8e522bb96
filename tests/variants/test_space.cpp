// Enumeration, rules, collapse of unread axes, key spelling and stability.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include <fmt/format.h>

#include "test_support.h"
#include "variants/key.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace {
using namespace aovar::variants;
using aovar::test::ScopedEnv;

Manifest shipped_manifest() { return load_manifest(aovar::test::source_dir() / "shader_src/aovar.toml"); }

TEST(Space, CountsFollowTheProductAndTheRules) {
  Manifest m = shipped_manifest();
  VariantSpace s = build_space(m);
  std::uint64_t product = 1;
  for (const auto& values : m.values) product *= values.size();
  EXPECT_EQ(s.space, product);
  std::uint64_t dropped = 0;
  for (auto d : s.rule_drops) dropped += d;
  EXPECT_EQ(s.after_rules + dropped, s.space);
  EXPECT_EQ(s.pruned.size(), dropped);
  EXPECT_LE(s.collapsed, s.after_rules);
  EXPECT_GE(s.variants.size(), 700u) << "issue 2: at least 700 Alchemy variants";
  for (std::size_t r = 0; r < m.rules.size(); ++r) EXPECT_GT(s.rule_drops[r], 0u) << "rule " << r;
}

// Sets an environment variable for one scope (tests run one per process under ctest, but not under a
// plain test-binary run).
std::string space_error(const Manifest& m) {
  try {
    build_space(m);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Space, AProductAboveTheCapIsRefusedBeforeItIsEnumerated) {
  Manifest m = shipped_manifest();
  const std::uint64_t product = build_space(m).space;
  ASSERT_LT(product, kDefaultMaxSpacePoints) << "the default manifest fits the default cap";
  {
    ScopedEnv cap(kMaxSpaceVariable, std::to_string(product - 1).c_str());
    const std::string e = space_error(m);
    EXPECT_NE(e.find("aovar.toml:"), std::string::npos) << e;
    EXPECT_NE(e.find(fmt::format("the axes multiply to {} points, more than the {}", product, product - 1)),
              std::string::npos) << e;
    EXPECT_NE(e.find("raise the cap with AOVAR_MAX_SPACE=N"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  {
    ScopedEnv cap(kMaxSpaceVariable, std::to_string(product).c_str());
    EXPECT_EQ(build_space(m).space, product) << "the cap is inclusive";
  }
  for (const char* bad : {"-5", "0", "lots", "12x"}) {
    ScopedEnv cap(kMaxSpaceVariable, bad);
    EXPECT_NE(space_error(m).find("AOVAR_MAX_SPACE="), std::string::npos) << bad;
  }
  // 128 values on each of the 10 axes (2^70) overflow 64 bits: still one line, no wrap-around to a small product.
  Manifest wide = m;
  for (auto& values : wide.values) values.resize(128, values.front());
  const std::string e = space_error(wide);
  EXPECT_NE(e.find("over 2^64 points"), std::string::npos) << e;
}

TEST(Space, RulesDropWhatTheySayAndNothingElse) {
  Manifest m = shipped_manifest();
  VariantSpace s = build_space(m);
  for (const auto& v : s.variants) {
    // skip progressive without blur; only r16f with mediump (the default manifest's rules)
    EXPECT_FALSE(v.key.find("-p1-") != std::string::npos && v.key.find("-bno-") != std::string::npos) << v.key;
    EXPECT_FALSE(v.key.find("-d32-") != std::string::npos && v.key.ends_with("-mp")) << v.key;
  }
  // Every pruned variant names a rule whose predicate matches it.
  for (const auto& p : s.pruned) {
    ASSERT_GE(p.rule, 0);
    ASSERT_LT(p.rule, static_cast<int>(m.rules.size()));
  }
  auto pruned_key = [&](const std::string& k) {
    return std::any_of(s.pruned.begin(), s.pruned.end(), [&](const PrunedVariant& p) { return p.key == k; });
  };
  EXPECT_TRUE(pruned_key("alchemy-s08-p1-nrg8-zdep-rst-d16-bno-x1-hp"));
  EXPECT_FALSE(pruned_key("alchemy-s08-p1-nrg8-zdep-rst-d16-bsep-x1-hp"));
}

TEST(Space, AxesAnAlgorithmDoesNotReadCollapse) {
  Manifest m = shipped_manifest();
  // The first algorithm alone, pretending it read no normals and no precision: those axes collapse to "_n"
  // and "_f".
  m.values[index(Axis::algorithm)].resize(1);
  m.values[index(Axis::depth_mip)].resize(1);  // off alone: its key token is left out either way
  auto first = std::find_if(m.algorithms.begin(), m.algorithms.end(),
                            [&](const Algorithm& a) { return a.name == m.value(Axis::algorithm, 0).text; });
  ASSERT_NE(first, m.algorithms.end());
  auto& reads = first->reads;
  reads.erase(std::remove(reads.begin(), reads.end(), Axis::normals), reads.end());
  reads.erase(std::remove(reads.begin(), reads.end(), Axis::precision), reads.end());
  // The G-buffer and blur stages still read normals/precision, so make them not read them either.
  for (auto& p : m.passes) {
    p.fragment.reads.clear();
  }
  m.rules.clear();
  VariantSpace s = build_space(m);
  std::set<std::string> keys;
  for (const auto& v : s.variants) {
    keys.insert(v.key);
    EXPECT_NE(v.key.find("-_n-"), std::string::npos) << v.key;
    EXPECT_TRUE(v.key.ends_with("-_f")) << v.key;
  }
  EXPECT_EQ(keys.size(), s.variants.size());
  EXPECT_EQ(s.collapsed * m.values[index(Axis::normals)].size() * m.values[index(Axis::precision)].size(), s.space);
}

TEST(Space, KeysAreCanonicalSortedAndStable) {
  Manifest m = shipped_manifest();
  VariantSpace a = build_space(m);
  VariantSpace b = build_space(shipped_manifest());
  ASSERT_EQ(a.variants.size(), b.variants.size());
  for (std::size_t i = 0; i < a.variants.size(); ++i) EXPECT_EQ(a.variants[i].key, b.variants[i].key);
  EXPECT_TRUE(std::is_sorted(a.variants.begin(), a.variants.end(),
                             [](const VariantEntry& x, const VariantEntry& y) { return x.key < y.key; }));
  // The documented spelling (variants/axes.h): a key users and caches rely on.
  Point p{};
  auto at = [&](Axis axis, const std::string& text) {
    const auto& vals = m.axis_values(axis);
    auto it = std::find_if(vals.begin(), vals.end(), [&](const AxisValue& v) { return v.text == text; });
    return static_cast<int>(it - vals.begin());
  };
  p[index(Axis::algorithm)] = at(Axis::algorithm, "alchemy");
  p[index(Axis::samples)] = at(Axis::samples, "8");
  p[index(Axis::progressive)] = at(Axis::progressive, "false");
  p[index(Axis::normals)] = at(Axis::normals, "rg8");
  p[index(Axis::position)] = at(Axis::position, "depth");
  p[index(Axis::reconstruct)] = at(Axis::reconstruct, "similar_triangles");
  p[index(Axis::depth_format)] = at(Axis::depth_format, "r16f");
  p[index(Axis::blur)] = at(Axis::blur, "separable");
  p[index(Axis::resolution)] = at(Axis::resolution, "0.5");
  p[index(Axis::precision)] = at(Axis::precision, "mediump");
  EXPECT_EQ(variant_key(m, p), "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x2-mp");
  p[index(Axis::normals)] = -1;
  EXPECT_EQ(variant_key(m, p), "alchemy-s08-p0-_n-zdep-rst-d16-bsep-x2-mp");
}

TEST(Space, ProgramsAreSharedBetweenVariants) {
  VariantSpace s = build_space(shipped_manifest());
  // The AO program does not read blur, resolution or depth format: 3 x 3 x 2 variants could share one.
  std::size_t ao_programs = std::count_if(s.programs.begin(), s.programs.end(),
                                          [](const ProgramSpec& p) { return p.key.rfind("alchemy-", 0) == 0; });
  EXPECT_LT(ao_programs * 4, s.variants.size());
  for (const auto& p : s.programs) {
    if (p.key == "fullscreen.vert") { EXPECT_TRUE(p.defines.empty()); }
    if (p.key.rfind("alchemy-s08-p1-", 0) == 0) {
      bool has_samples = false, has_progressive = false;
      for (const auto& [name, value] : p.defines) {
        has_samples |= name == "AO_SAMPLES" && value == "8";
        has_progressive |= name == "AO_PROGRESSIVE" && value == "1";
      }
      EXPECT_TRUE(has_samples && has_progressive) << p.key;
    }
  }
}

// depth_mip (issue 33) is optional: off is left out of keys, defines and program keys, so every variant and
// program from before the axis keeps its name and its source; on is "-zmip" and the wrapper ao/on/<method>.
TEST(Space, DepthMipOffLeavesNamesAsTheyWereAndOnIsZmip) {
  Manifest m = shipped_manifest();
  VariantSpace s = build_space(m);
  std::set<std::string> far_samplers;  // the methods whose [algorithms.*] reads name depth_mip
  for (const auto& a : m.algorithms)
    if (std::find(a.reads.begin(), a.reads.end(), Axis::depth_mip) != a.reads.end()) far_samplers.insert(a.name);
  ASSERT_FALSE(far_samplers.empty());
  std::set<std::string> with_mip;
  for (const auto& v : s.variants) {
    const bool on = value_text(m, v.point, Axis::depth_mip) == "on";
    EXPECT_EQ(v.key.ends_with("-zmip"), on) << v.key;
    EXPECT_EQ(std::count(v.key.begin(), v.key.end(), '-'), on ? 10 : 9) << v.key;
    auto parsed = parse_key(m, v.key);
    ASSERT_TRUE(parsed.has_value()) << v.key;
    EXPECT_EQ(*parsed, v.point) << v.key;
    if (!on) continue;
    with_mip.insert(value_text(m, v.point, Axis::algorithm));
    EXPECT_EQ(value_text(m, v.point, Axis::position), "depth") << v.key;
    auto off = with_axis(m, v.key, Axis::depth_mip, "off");
    ASSERT_TRUE(off.has_value()) << v.key;
    EXPECT_EQ(*off + "-zmip", v.key);
  }
  EXPECT_EQ(with_mip, far_samplers);
  for (const auto& p : s.programs) {
    const bool on = p.key.find("-zmip.") != std::string::npos;
    bool defined = false;
    for (const auto& [name, value] : p.defines) defined |= name.rfind("AO_DEPTH_MIP", 0) == 0;
    EXPECT_EQ(defined, on) << p.key;
    EXPECT_EQ(p.template_path.rfind("ao/on/", 0) == 0, on) << p.key << " from " << p.template_path;
    EXPECT_EQ(p.template_path.find("//"), std::string::npos) << p.template_path;
  }
  EXPECT_FALSE(parse_key(m, "crytek-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp-_m").has_value());
}

TEST(Space, GlobsSelectVariants) {
  Manifest m = shipped_manifest();
  VariantSpace s = build_space(m, {"alchemy-s04-*-x4-*"});
  ASSERT_FALSE(s.variants.empty());
  for (const auto& v : s.variants) EXPECT_NE(v.key.find("-x4-"), std::string::npos);
  EXPECT_EQ(s.variants.size() + s.filtered_out, s.collapsed);
}

}  // namespace
