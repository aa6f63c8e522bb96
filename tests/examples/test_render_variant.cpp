// The reverse check of issue 53 (points 3 and 4): examples/render_variant, which links only the generated library and
// the Vulkan loader, renders on aovar's own G-buffer (`aovar gbuffer`) the image aovar scored. A tiny `aovar ship`
// on builtin:atrium chooses a variant; its printed build line (with the other variants checked here added, and
// `--targets vulkan --emit cpp`) generates the one library the example is built against, once; then for the choice
// on the held-out view, one variant of each method, one with the separable blur at half resolution and a
// progressive one, the example's image must be aovar's to 1/255 and score the same RMSE against the reference to 4
// decimals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "lavapipe_support.h"
#include "metrics/metrics.h"
#include "reference/reference.h"
#include "test_support.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;

const char* kScene = "builtin:atrium";
const char* kSize = "64x36";

// tests/ship/test_ship_cli.cpp's slice and baseline, raced on lavapipe (no RADV needed) with each candidate's
// timing capped at 0.2 s.
std::string ship_args(const fs::path& out, const fs::path& cache) {
  return fmt::format("ship --scene {} --variants 'alchemy-s08-p0-*-zdep-rst-d16-bsep-x1-hp' "
                     "--variants 'sao-s0[48]-*-d16-bsep-x1-hp' --variants 'hbao-s08-p0-*-d16-bsep-x1-hp' "
                     "--budget-of alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp --backend lavapipe --reps-cap-s 0.2 "
                     "--size {} --fit-size 32x18 --evaluations 2 --rays 16 --cache-dir {} --out {}",
                     kScene, kSize, cache.string(), out.string());
}

// What follows "build it: aovar " in ship's output.
std::string build_line(const std::string& output) {
  const auto at = output.find("build it: aovar ");
  if (at == std::string::npos) return "";
  const auto start = at + std::string("build it: aovar ").size();
  return output.substr(start, output.find('\n', start) - start);
}

std::string quoted_after(const std::string& line, const std::string& option) {
  std::smatch m;
  return std::regex_search(line, m, std::regex(option + " '([^']+)'")) ? m[1].str() : "";
}

// The first key `aovar list` gives for `glob` ("" when none).
std::string first_key(const std::string& glob) {
  const CommandResult r = run_aovar(fmt::format("list --variants '{}'", glob));
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] != '#') return line;
  return "";
}

// One variant of each method (the first s08 separable full-resolution key per algorithm, so a new method is
// covered without an edit), SAO among them with its pyramid; the separable blur at half resolution, a progressive
// one, one reading the depth MIP pyramid, the bilateral blur at quarter resolution.
std::vector<std::string> shapes() {
  std::vector<std::string> keys;
  std::set<std::string> methods;
  std::istringstream lines(run_aovar("list --variants '*-s08-p0-*-bsep-x1-hp'").output);
  for (std::string key; std::getline(lines, key);)
    if (!key.empty() && key[0] != '#' && methods.insert(key.substr(0, key.find('-'))).second) keys.push_back(key);
  for (const char* glob : {"*-s08-p0-*-bsep-x2-hp", "*-s08-p1-*-bsep-x1-hp", "*-s08-p0-*-bsep-x1-hp-zmip",
                           "*-s08-p0-*-bbil-x4-hp"})
    keys.push_back(first_key(glob));
  return keys;
}

// The printed build line with its output folder moved to `out`, `more` variants added, and only what the
// example needs emitted.
std::string generate_args(std::string line, const fs::path& out, const std::vector<std::string>& more,
                          const fs::path& cache) {
  line = std::regex_replace(line, std::regex(" --out \\S+"), "");
  for (const std::string& key : more) line += fmt::format(" --variants '{}'", key);
  return line + fmt::format(" --targets vulkan --emit cpp --cache-dir {} --out {}", cache.string(), out.string());
}

// The example configured and built against the generated library in `shaders`; its executable.
fs::path build_example(const fs::path& shaders, const fs::path& build) {
  const CommandResult configure = run_command(fmt::format(
      "{} -S {} -B {} -DRENDER_VARIANT_SHADERS={} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER={}", AOVAR_CMAKE,
      (source_dir() / "examples" / "render_variant").string(), build.string(), shaders.string(), AOVAR_CXX));
  EXPECT_EQ(configure.status, 0) << configure.output;
  const CommandResult compile = run_command(fmt::format("{} --build {} -j 2", AOVAR_CMAKE, build.string()));
  EXPECT_EQ(compile.status, 0) << compile.output;
  return build / "render_variant";
}

// aovar's still of `key` on `view` under `root` (a measure folder, or ship's output holding several).
fs::path aovar_image(const fs::path& root, const std::string& view, const std::string& key) {
  const fs::path tail = fs::path("lavapipe") / view / (key + ".pfm");
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.path().string().size() >= tail.string().size() &&
        e.path().string().compare(e.path().string().size() - tail.string().size(), std::string::npos, tail.string()) == 0)
      return e.path();
  return {};
}

float max_difference(const image::FloatImage& a, const image::FloatImage& b) {
  float worst = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const float d = std::fabs(a.pixels[i] - b.pixels[i]);
    worst = std::isnan(d) ? INFINITY : std::max(worst, d);
  }
  return worst;
}

// The row's RMSE of `key` on `view` in a cost table's or measure.json's rows (NaN when absent).
double row_rmse(const json& rows, const std::string& key, const std::string& view) {
  for (const json& r : rows)
    if (r.at("variant") == key && r.at("view") == view && r.contains("error") && r.at("error").contains("rmse"))
      return r.at("error").at("rmse").get<double>();
  return NAN;
}

struct Scored {
  fs::path image;      // aovar's still
  fs::path reference;  // the reference stem its rmse is against (images/reference/<view>)
  double rmse;         // its row's
};

// Writes the held-out view's G-buffer for `key`, runs the example on it and holds its image to aovar's.
void expect_reproduced(const fs::path& example, const fs::path& dir, const std::string& key, const std::string& view,
                       float radius, const Scored& scored) {
  SCOPED_TRACE(key);
  ASSERT_FALSE(scored.image.empty()) << "aovar wrote no image of " << key;
  const fs::path gbuffer = dir / (key + ".gbuffer"), ours = dir / (key + ".pfm");
  const CommandResult g = run_aovar(fmt::format("gbuffer --scene {} --view {} --variant {} --size {} --radius {} "
                                                "--cache-dir {} --out {}", kScene, view, key, kSize, radius,
                                                (dir / "cache").string(), gbuffer.string()));
  ASSERT_EQ(g.status, 0) << g.output;
  const CommandResult r = run_command(fmt::format("{} {} {} {}", example.string(), key, gbuffer.string(), ours.string()));
  ASSERT_EQ(r.status, 0) << r.output;
  const image::FloatImage a = image::read_pfm(ours), b = image::read_pfm(scored.image);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  EXPECT_LE(max_difference(a, b), 1.0f / 255.0f) << ours << " against " << scored.image;
  const reference::ReferenceImage truth = reference::load_reference(scored.reference);
  EXPECT_EQ(fmt::format("{:.4f}", metrics::compare(a, truth.visibility, truth.background).rmse),
            fmt::format("{:.4f}", scored.rmse));
}

// A bad input is refused in one line naming it, with exit status 2.
void expect_refused(const fs::path& example, const std::string& args, const std::string& names) {
  const CommandResult r = run_command(example.string() + " " + args);
  EXPECT_EQ(r.status, 2) << r.output;
  const std::string line = r.output.substr(0, r.output.find_last_not_of('\n') + 1);
  EXPECT_TRUE(one_line_error_with(line, names)) << args;
}

void expect_bad_inputs_refused(const fs::path& example, const fs::path& dir, const std::string& key) {
  const fs::path gbuffer = dir / (key + ".gbuffer"), out = dir / "refused.pfm";
  write_text(dir / "foreign.gbuffer", "P5\n64 36\n255\n");
  expect_refused(example, fmt::format("{} {} {}", key, (dir / "missing.gbuffer").string(), out.string()), "missing.gbuffer");
  expect_refused(example, fmt::format("{} {} {}", key, (dir / "foreign.gbuffer").string(), out.string()), "foreign.gbuffer");
  expect_refused(example, fmt::format("no-such-variant {} {}", gbuffer.string(), out.string()), "no-such-variant");
  expect_refused(example, fmt::format("{} {} {} --device no-such-device", key, gbuffer.string(), out.string()),
                 "--device no-such-device");
  expect_refused(example, key, "usage: render_variant KEY GBUFFER_FILE OUT.pfm");
  EXPECT_FALSE(fs::exists(out));
}

TEST(RenderVariantExample, RendersWhatAovarScoredFromTheGeneratedLibraryAlone) {
  REQUIRE_LAVAPIPE();
  TempDir dir;
  const fs::path ship = dir / "ship", cache = dir / "cache";
  const CommandResult shipped = run_aovar(ship_args(ship, cache));
  ASSERT_EQ(shipped.status, 0) << shipped.output;
  const std::string line = build_line(shipped.output), chosen = quoted_after(line, "--variants");
  ASSERT_FALSE(chosen.empty()) << shipped.output;
  EXPECT_NE(line.find("--calibration"), std::string::npos) << "the build line carries the fit: " << line;

  std::vector<std::string> others = shapes();
  std::erase(others, chosen);
  ASSERT_GE(others.size(), 3u);
  const CommandResult generated = run_aovar(generate_args(line, dir / "shaders", others, cache));
  ASSERT_EQ(generated.status, 0) << generated.output;
  const fs::path example = build_example(dir / "shaders", dir / "build");
  ASSERT_TRUE(fs::exists(example));

  // The choice: the image and cost-table row ship scored on the held-out view.
  const json table = read_json(ship / "cost_table.json");
  const float radius = table.at("meta").at("scenes").at(0).at("radius").get<float>();
  const std::string held_out = table.at("meta").at("ship").at("holdout_views").at(0).get<std::string>();
  const fs::path ship_image = aovar_image(ship, held_out, chosen);
  expect_reproduced(example, dir.path(), chosen, held_out, radius,
                    {ship_image, ship_image.parent_path().parent_path().parent_path() / "reference" / held_out,
                     row_rmse(table.at("rows"), chosen, held_out)});

  // The other shapes, measured by aovar with the same fit.
  std::string measure = fmt::format("measure --scene {} --view {} --size {} --radius {} --reps 1 --warmup 0 --no-prune "
                                    "--calibration {} --reference --rays 16 --cache-dir {} --out {}",
                                    kScene, held_out, kSize, radius, (ship / "calibration.json").string(),
                                    cache.string(), (dir / "measure").string());
  for (const std::string& key : others) measure += fmt::format(" --variants '{}'", key);
  const CommandResult measured = run_aovar(measure);
  ASSERT_EQ(measured.status, 0) << measured.output;
  const json rows = read_json(dir / "measure" / "measure.json").at("rows");
  for (const std::string& key : others)
    expect_reproduced(example, dir.path(), key, held_out, radius,
                      {aovar_image(dir / "measure", held_out, key), dir / "measure" / "images" / "reference" / held_out,
                       row_rmse(rows, key, held_out)});
  expect_bad_inputs_refused(example, dir.path(), chosen);
}

}  // namespace
}  // namespace aovar::test
