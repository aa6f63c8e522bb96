// Issue 34, outputs: generate with a selection that holds no variant (a glob typo, rules that drop everything)
// is an error, exit 2, before anything in the output folder is written or removed.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

// A populated output folder, and what it holds (but the folder's lock, which every writer takes first).
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != ".aovar.lock") m[e.path().lexically_relative(dir).string()] = util::read_file(e.path()).value();
  return m;
}

TEST(GenerateSelection, AGlobMatchingNothingIsAnErrorThatRemovesNothing) {
  TempDir dir;
  const fs::path out = dir / "G";
  util::write_atomic(out / "variants.json", "{}\n");
  util::write_atomic(out / "vulkan/alchemy-s08.frag.spv", "spirv");
  util::write_atomic(out / "gl45/alchemy-s08.frag", "source");
  const auto before = contents(out);
  for (const std::string globs : {"--variants 'gtoa-s*'", "--variants 'nothing' --variants 'gtao-s99*'"}) {
    const auto r = test::run_aovar("generate --manifest " + (test::source_dir() / "shader_src/aovar.toml").string() + " " + globs + " --out " +
                                   out.string() + " --no-cache");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_TRUE(test::has_text(r.output, "aovar.toml: error: --variants '")) << r.output;
    EXPECT_TRUE(test::has_text(r.output, "matches none of the")) << r.output;
    EXPECT_TRUE(test::has_text(r.output, "nothing was written or removed")) << r.output;
    EXPECT_EQ(contents(out), before);
  }
}

TEST(GenerateSelection, RulesThatDropEverythingAreAnErrorThatRemovesNothing) {
  TempDir dir;
  const fs::path manifest = test::copy_shader_src(dir);
  test::append_line(manifest, "[[rules]]\nskip = { precision = [\"highp\", \"mediump\"] }\nreason = \"typo\"");
  const fs::path out = dir / "G";
  util::write_atomic(out / "vulkan/alchemy-s08.frag.spv", "spirv");
  const auto before = contents(out);
  const auto r = test::run_aovar("generate --manifest " + manifest.string() + " --out " + out.string() + " --no-cache");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(test::has_text(r.output, "error: the manifest's rules drop all")) << r.output;
  EXPECT_EQ(contents(out), before);
}

}  // namespace
