// The guard against an accidental whole-space run (issue 38, src/cli/whole_space.h): `sweep` and `measure`
// without --variants on the default manifest refuse at once in one line naming the variant count, the
// estimated time and --all, and write nothing; --variants or --all let the run start.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>

#include "test_support.h"

namespace {
using namespace aovar::test;

TEST(WholeSpace, SweepAndMeasureWithoutVariantsRefuseInOneLine) {
  TempDir dir;
  for (const std::string command : {"sweep", "measure"}) {
    const auto out = dir / ("out-" + command);
    const auto r = run_aovar(command + " --scene builtin:stairs --size 32x18 --out " + out.string());
    EXPECT_EQ(r.status, 2) << command << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << command << ": one line: " << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(command + ": no --variants selects all ([0-9]+) variants of "
                                                          "[^ ]+: about ([0-9]+) (h|min) ")))
        << r.output;
    EXPECT_GT(std::stoi(m[1]), 1000) << "the default manifest's space: " << r.output;
    EXPECT_TRUE(has_text(r.output, "--all")) << r.output;
    EXPECT_TRUE(has_text(r.output, "--variants GLOB")) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << command << " wrote into its output folder";
  }
  // The sweep covers every view of the scene (3), measure its first: the sweep's estimate is 3 times measure's.
  const auto sweep = run_aovar("sweep --scene builtin:stairs --out " + (dir / "s").string());
  const auto three = run_aovar("measure --view overview --view closeup --view background --out " + (dir / "m").string());
  EXPECT_TRUE(has_text(sweep.output, "(3 view(s) each")) << sweep.output;
  EXPECT_TRUE(has_text(three.output, "(3 view(s) each")) << three.output;
}

TEST(WholeSpace, AllOrVariantsPassTheGuard) {
  TempDir dir;
  // --all passes the guard; the run then fails on its scene, before compiling anything.
  const auto all = run_aovar("measure --all --scene /nonexistent/scene.obj --out " + (dir / "a").string());
  EXPECT_NE(all.status, 0) << all.output;
  EXPECT_FALSE(has_text(all.output, "no --variants")) << all.output;
  EXPECT_TRUE(has_text(all.output, "/nonexistent/scene.obj")) << all.output;
  // A selection, however wide, is what the user asked for.
  const auto wide = run_aovar("measure --variants '*' --scene /nonexistent/scene.obj --out " + (dir / "w").string());
  EXPECT_FALSE(has_text(wide.output, "no --variants")) << wide.output;
}

}  // namespace
