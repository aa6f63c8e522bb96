// A method is data (issue 52): an 11th AO method is a template and a manifest entry. A copy of shader_src
// gains a toy method, the baseline method's template and [algorithms.*] entry under a new name with no
// colour, and the built CLI takes it through list, generate, measure --reference, report and select with no
// source change; the report draws it in the colour the manifest's palette gives it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "measure/measure.h"
#include "test_support.h"
#include "util/fs.h"
#include "variants/key.h"
#include "variants/manifest.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

constexpr const char* kToy = "toy";
// The toy's variants: both normal sources the shared-code rule leaves a method other than the baseline's.
constexpr const char* kToyGlob = "toy-s08-p0-*-d16-bsep-x1-hp";

// The [algorithms.<name>] table of `text`, up to the blank line that ends it.
std::string algorithm_table(const std::string& text, const std::string& name) {
  const std::string header = "[algorithms." + name + "]\n";
  const std::size_t begin = text.find(header);
  if (begin == std::string::npos) throw std::runtime_error("no " + header + " in the manifest");
  const std::size_t end = text.find("\n\n", begin);
  return text.substr(begin + header.size(), end == std::string::npos ? std::string::npos : end - begin - header.size() + 1);
}

// The table's lines but its colour and display name: the toy must get both without them.
std::string without_style(const std::string& table) {
  std::string out;
  for (std::size_t at = 0; at < table.size();) {
    std::size_t end = table.find('\n', at);
    end = end == std::string::npos ? table.size() : end + 1;
    const std::string line = table.substr(at, end - at);
    if (line.rfind("color", 0) != 0 && line.rfind("display_name", 0) != 0) out += line;
    at = end;
  }
  return out;
}

// The copy of shader_src with the toy added: its template, its name on the algorithm axis, its table.
fs::path add_toy_method(const TempDir& dir) {
  const fs::path manifest = copy_shader_src(dir);
  const auto shipped = variants::load_manifest(manifest);
  const std::string source = variants::value_text(shipped, variants::parse_key(shipped, measure::kDefaultBaseline).value(),
                                                  variants::Axis::algorithm);
  fs::copy_file(manifest.parent_path() / "ao" / (source + ".glsl"), manifest.parent_path() / "ao" / (std::string(kToy) + ".glsl"));
  const std::string text = util::read_file(manifest).value();
  const std::string axis = "\nalgorithm    = [";
  if (text.find(axis) == std::string::npos) throw std::runtime_error("no algorithm axis line in the manifest");
  replace_in_file(manifest, axis, axis + "\"" + kToy + "\", ");
  append_line(manifest, "\n[algorithms." + std::string(kToy) + "]\ndisplay_name = \"Toy AO\"\n" +
                            without_style(algorithm_table(text, source)));
  return manifest;
}

TEST(NewMethod, ToyMethodGoesThroughListGenerateMeasureReportAndSelect) {
  TempDir dir;
  const fs::path manifest = add_toy_method(dir);
  const auto parsed = variants::load_manifest(manifest);
  const variants::Algorithm* toy = parsed.algorithm(kToy);
  ASSERT_NE(toy, nullptr);
  EXPECT_EQ(toy->display_name, "Toy AO");
  for (const auto& other : parsed.algorithms)
    if (other.name != kToy) {
      EXPECT_NE(toy->color, other.color) << "the palette gives the toy a colour of its own";
    }
  const std::string m = " --manifest " + manifest.string() + " --cache-dir " + (dir / "cache").string();

  const auto list = run_aovar("list" + m + " --variants '" + kToyGlob + "'");
  ASSERT_EQ(list.status, 0) << list.output;
  EXPECT_TRUE(has_text(list.output, "toy-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp")) << list.output;

  const auto generate = run_aovar("generate" + m + " --targets vulkan --variants '" + kToyGlob + "' --out " + (dir / "gen").string());
  ASSERT_EQ(generate.status, 0) << generate.output;
  EXPECT_TRUE(has_text(util::read_file(dir / "gen" / "variants.json").value(), "\"toy-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp\""));

  const auto measure = run_aovar("measure" + m + " --scene builtin:stairs --size 64x36 --reps 2 --warmup 0 --reference "
                                 "--no-images --variants '" + kToyGlob + "' --variants " + measure::kDefaultBaseline +
                                 " --out " + (dir / "m").string());
  ASSERT_EQ(measure.status, 0) << measure.output;
  int toy_rows = 0;
  const nlohmann::json measured = read_json(dir / "m" / "measure.json");
  for (const auto& row : measured.at("rows"))
    if (row.at("variant").get<std::string>().rfind("toy-", 0) == 0) {
      ++toy_rows;
      EXPECT_TRUE(row.at("error").is_object()) << "scored against the reference: " << row.dump();
    }
  EXPECT_EQ(toy_rows, 2) << measure.output;

  const std::string table = " --table " + (dir / "m" / "measure.json").string();
  const auto report = run_aovar("report" + table + " --manifest " + manifest.string() + " --out " + (dir / "r").string());
  ASSERT_EQ(report.status, 0) << report.output;
  const std::string html = util::read_file(dir / "r" / "report.html").value();
  EXPECT_TRUE(has_text(html, "<span style=\"color:" + toy->color + "\">&#9679;</span> toy (Toy AO)")) << "in the legend";
  EXPECT_TRUE(has_text(html, "fill=\"" + toy->color + "\"")) << "its points and bars in its colour";

  // The toy is one of the three candidates: select names every one that meets the request.
  const auto select = run_aovar("select" + table + " --max-error 1");
  ASSERT_EQ(select.status, 0) << select.output;
  EXPECT_TRUE(has_text(select.output, "toy-s08-p0-")) << select.output;
}

}  // namespace
}  // namespace aovar::test
