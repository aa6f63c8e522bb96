// Manifest errors carry file, line and column; good manifests parse into the expected structure.
#include <gtest/gtest.h>

#include <algorithm>

#include "test_support.h"
#include "variants/key.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace {
using namespace aovar::variants;

// A small, complete manifest; tests edit one piece of it.
const std::string kBase = R"([manifest]
targets = ["vulkan"]
[axes]
algorithm = ["alchemy"]
samples = [4, 8]
progressive = [false]
normals = ["rg8", "depth"]
position = ["depth", "position"]
reconstruct = ["similar_triangles", "inverse_projection"]
depth_format = ["r16f"]
blur = ["none", "separable"]
resolution = [1.0, 0.5]
precision = ["highp"]
[[rules]]
skip = { resolution = 0.5, blur = "none" }
reason = "blocky"
[pipeline]
reads = ["depth_format", "resolution"]
[passes.gbuffer]
vertex = { template = "passes/gbuffer.vert" }
fragment = { template = "passes/gbuffer.frag", reads = ["normals", "position"] }
[passes.ao]
vertex = { template = "passes/fullscreen.vert" }
fragment = { template = "ao/{algorithm}.glsl", reads = "algorithm" }
[passes.blur]
when = { blur = "separable" }
vertex = { template = "passes/fullscreen.vert" }
fragment = { template = "passes/blur_{blur}.frag" }
[algorithms.alchemy]
reads = ["samples", "normals", "position", "reconstruct"]
params.intensity = { default = 1.0, min = 0.0, max = 4.0 }
)";

std::string with(const std::string& from, const std::string& to) {
  std::string s = kBase;
  auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// Expects a ManifestError whose message starts with "m.toml:<line>:<column>: error:" and contains `what`.
void expect_error(const std::string& text, int line, int column, const std::string& what) {
  const std::string msg = aovar::test::thrown_message<ManifestError>([&] {
    Manifest m = parse_manifest(text, "m.toml"); build_space(m);
  });
  EXPECT_EQ(msg.rfind("m.toml:" + std::to_string(line) + ":" + std::to_string(column) + ": error: ", 0), 0u) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
}

TEST(Manifest, ParsesAxesRulesPassesAndParams) {
  Manifest m = parse_manifest(kBase, "m.toml");
  EXPECT_EQ(m.axis_values(Axis::samples).size(), 2u);
  EXPECT_EQ(m.value(Axis::resolution, 1).text, "0.5");
  ASSERT_EQ(m.passes.size(), 3u);
  EXPECT_EQ(m.passes[0].name, "gbuffer");  // file order, not alphabetical
  EXPECT_EQ(m.passes[2].name, "blur");
  EXPECT_TRUE(m.passes[1].fragment.reads_algorithm);
  ASSERT_EQ(m.rules.size(), 1u);
  EXPECT_EQ(m.rules[0].pos.line, 15);
  ASSERT_NE(m.algorithm("alchemy"), nullptr);
  EXPECT_EQ(m.algorithm("alchemy")->params.at(0).name, "intensity");
}

// depth_mip is the one optional axis (issue 33): a manifest written before it has it at "off" alone, no stage
// reads it, and every key is spelled and parsed as before.
TEST(Manifest, AManifestWithoutDepthMipKeepsItsKeys) {
  Manifest m = parse_manifest(kBase, "m.toml");
  ASSERT_EQ(m.axis_values(Axis::depth_mip).size(), 1u);
  EXPECT_EQ(m.axis_values(Axis::depth_mip)[0].text, "off");
  VariantSpace s = build_space(m);
  ASSERT_FALSE(s.variants.empty());
  for (const auto& v : s.variants) {
    EXPECT_EQ(v.point[index(Axis::depth_mip)], -1) << v.key;
    EXPECT_EQ(std::count(v.key.begin(), v.key.end(), '-'), 9) << v.key;
    auto parsed = parse_key(m, v.key);
    ASSERT_TRUE(parsed.has_value()) << v.key;
    EXPECT_EQ(*parsed, v.point) << v.key;
  }
  EXPECT_FALSE(parse_key(m, s.variants.front().key + "-zmip").has_value()) << "the manifest has no on value";
  // The other axes stay required.
  expect_error(with("precision = [\"highp\"]\n", ""), 3, 1, "[axes] is missing axis 'precision'");
}

// [algorithms.*] display_name and color say how reports show a method: a method without them is shown under
// its name in the palette's colour at its table's place; a bad colour is a one-line error at its value.
TEST(Manifest, AlgorithmDisplayNameAndColor) {
  Manifest plain = parse_manifest(kBase, "m.toml");
  EXPECT_EQ(plain.algorithm("alchemy")->display_name, "alchemy");
  EXPECT_EQ(plain.algorithm("alchemy")->color, method_palette_color(0));
  Manifest styled = parse_manifest(
      with("[algorithms.alchemy]\n", "[algorithms.alchemy]\ndisplay_name = \"Alchemy AO\"\ncolor = \"#1F77b4\"\n"), "m.toml");
  EXPECT_EQ(styled.algorithm("alchemy")->display_name, "Alchemy AO");
  EXPECT_EQ(styled.algorithm("alchemy")->color, "#1F77b4");
  for (const char* bad : {"\"blue\"", "\"#1f77b\"", "\"#1f77bg\"", "\"1f77b4f\""})
    expect_error(with("[algorithms.alchemy]\n", std::string("[algorithms.alchemy]\ncolor = ") + bad + "\n"), 30, 9,
                 "[algorithms.alchemy] color");
  expect_error(with("[algorithms.alchemy]\n", "[algorithms.alchemy]\ncolor = \"blue\"\n"), 30, 9,
               "[algorithms.alchemy] color 'blue' must be \"#rrggbb\"");
  expect_error(with("[algorithms.alchemy]\n", "[algorithms.alchemy]\ncolor = 3\n"), 30, 9, "color must be a string");
  expect_error(with("[algorithms.alchemy]\n", "[algorithms.alchemy]\ndisplay_name = \"\"\n"), 30, 16, "must not be empty");
}

// The algorithm axis takes any method the manifest names (its template and table are all a method needs);
// a name that cannot be a key token, define and file name is refused.
TEST(Manifest, AlgorithmNamesAreTheManifests) {
  Manifest m = parse_manifest(with("algorithm = [\"alchemy\"]", "algorithm = [\"alchemy\", \"toy_2\"]") +
                                  "[algorithms.toy_2]\nreads = [\"samples\"]\n",
                              "m.toml");
  ASSERT_NE(m.algorithm("toy_2"), nullptr);
  EXPECT_EQ(m.algorithm("toy_2")->color, method_palette_color(1)) << "the second table in the file";
  VariantSpace s = build_space(m);
  const auto toy = std::find_if(s.variants.begin(), s.variants.end(), [](const auto& v) { return v.key.rfind("toy_2-s04-", 0) == 0; });
  ASSERT_NE(toy, s.variants.end());
  EXPECT_EQ(parse_key(m, toy->key), toy->point);
  expect_error(with("algorithm = [\"alchemy\"]", "algorithm = [\"alchemy\", \"Toy-1\"]"), 4, 25,
               "'Toy-1' cannot be a value of axis 'algorithm'");
}

TEST(Manifest, UnknownAxisNamesItsPosition) {
  expect_error(with("precision = [\"highp\"]", "precisoin = [\"highp\"]"), 13, 1, "unknown axis 'precisoin'");
}

TEST(Manifest, BadValueNamesItsPosition) {
  expect_error(with("normals = [\"rg8\", \"depth\"]", "normals = [\"rg8\", \"rgb9\"]"), 7, 19,
               "'rgb9' is not a value of axis 'normals'");
  expect_error(with("resolution = [1.0, 0.5]", "resolution = [1.0, 0.3]"), 12, 20, "resolution must be 1/k");
  expect_error(with("samples = [4, 8]", "samples = [4, \"8\"]"), 5, 15, "integers");
}

TEST(Manifest, RuleThatMatchesNothingIsAnError) {
  // Every variant with blur = none already has blur = none: the rule can never drop anything.
  expect_error(with("skip = { resolution = 0.5, blur = \"none\" }", "when = { blur = \"none\" }\nonly = { blur = \"none\" }"),
               15, 8, "matches no variant");
}

TEST(Manifest, NotExcludesListedValuesAndMatchesTheRest) {
  Manifest m = parse_manifest(with("skip = { resolution = 0.5, blur = \"none\" }",
                                   "skip = { resolution = { not = 1.0 }, blur = \"none\" }"), "m.toml");
  auto s = build_space(m);
  for (const auto& v : s.variants) EXPECT_FALSE(v.key.find("-x2-") != std::string::npos && v.key.find("-bno-") != std::string::npos) << v.key;
  // A pass run for every normals value but depth: its `when` matches rg8 only.
  Manifest p = parse_manifest(with("when = { blur = \"separable\" }", "when = { blur = \"separable\", normals = { not = \"depth\" } }"), "m.toml");
  ASSERT_EQ(p.passes.size(), 3u);
  Point rg8{}, depth{};
  depth[index(Axis::normals)] = 1;
  depth[index(Axis::blur)] = rg8[index(Axis::blur)] = 1;
  EXPECT_TRUE(p.passes[2].when.matches(rg8));
  EXPECT_FALSE(p.passes[2].when.matches(depth));
  expect_error(with("skip = { resolution = 0.5,", "skip = { resolution = { not = [1.0, 0.5] },"), 15, 23,
               "excludes every value of resolution");
  expect_error(with("skip = { resolution = 0.5,", "skip = { resolution = { nor = 1.0 },"), 15, 23,
               "takes a value, a list of values or { not = ... }");
}

TEST(Manifest, RuleValueMustBeListedInAxes) {
  expect_error(with("skip = { resolution = 0.5,", "skip = { resolution = 0.25,"), 15, 23,
               "value 0.25 is not listed in [axes].resolution");
}

TEST(Manifest, DuplicateKeyIsReportedByPosition) {
  expect_error(with("samples = [4, 8]", "samples = [4, 8]\nsamples = [16]"), 6, 11, "cannot redefine");
}

TEST(Manifest, UnknownKeyAndMissingReason) {
  expect_error(with("reason = \"blocky\"", "reasn = \"blocky\""), 16, 1, "unknown key 'reasn'");
  expect_error(with("reason = \"blocky\"\n", ""), 14, 1, "needs a 'reason'");
}

TEST(Manifest, ParamDefaultOutsideRange) {
  expect_error(with("default = 1.0, min = 0.0, max = 4.0", "default = 5.0, min = 0.0, max = 4.0"), 31, 32,
               "outside [0, 4]");
}

TEST(Manifest, MissingFileIsOneLine) {
  try {
    load_manifest("/nonexistent/aovar.toml");
    FAIL();
  } catch (const ManifestError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/aovar.toml: error: cannot read"), std::string::npos);
  }
}

}  // namespace
