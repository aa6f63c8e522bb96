// The CLI as users meet it: one-line errors with exit 2 (every exit status: test_cli_scripts.cpp), list output,
// generate's no-op path.
#include <gtest/gtest.h>

#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;

TEST(Cli, ListPrintsOneKeyPerLineAndTheCounts) {
  auto r = test::run_aovar("list --manifest shader_src/aovar.toml --targets vulkan --variants 'alchemy-s04-p0-nrg8-*'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.rfind("alchemy-s04-p0-nrg8-", 0), 0u) << r.output.substr(0, 200);
  EXPECT_NE(r.output.find("# space "), std::string::npos);
  EXPECT_NE(r.output.find(" / rules "), std::string::npos);
  EXPECT_NE(r.output.find(" / dedup "), std::string::npos);
}

TEST(Cli, BadManifestGivesOneLineErrorAndExitTwo) {
  test::TempDir dir;
  fs::path manifest = test::copy_shader_src(dir);
  test::replace_in_file(manifest, "normals      = [\"rgb8\"", "normals      = [\"rgb9\"");
  auto r = test::run_aovar("list --manifest " + manifest.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("aovar.toml:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(": error: 'rgb9' is not a value of axis 'normals'"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

TEST(Cli, CompileErrorsExitNonZeroAndWriteNothing) {
  test::TempDir dir;
  fs::path manifest = test::copy_shader_src(dir);
  test::append_line(dir / "shader_src/passes/progressive.frag", "this is not glsl;");
  auto r = test::run_aovar("generate --no-cache --targets gles30 --manifest " + manifest.string() + " --out " +
                           (dir / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("passes/progressive.frag:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nothing was written"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Cli, SecondGenerateIsANoOp) {
  test::TempDir dir;
  std::string args = "generate --targets vulkan --variants 'alchemy-s04-*' --cache-dir " + (dir / "cache").string() +
                     " --out " + (dir / "out").string() + " --stamp " + (dir / "stamp").string();
  auto first = test::run_aovar(args);
  ASSERT_EQ(first.status, 0) << first.output;
  auto before = fs::last_write_time(dir / "out/variants.json");
  auto second = test::run_aovar(args);
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_NE(second.output.find("up to date: nothing compiled, no file written"), std::string::npos) << second.output;
  EXPECT_EQ(fs::last_write_time(dir / "out/variants.json"), before);
  // Touching an output makes the next run check (and rewrite) it.
  test::append_line(dir / "out/variants.json", "garbage");
  auto third = test::run_aovar(args);
  EXPECT_NE(third.output.find("1 written"), std::string::npos) << third.output;
}

}  // namespace
