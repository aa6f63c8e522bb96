// When nothing is left to measure, the error blames what emptied the selection (issue 34, misleading
// errors): a manifest whose rules drop every variant is not "no variant matches --variants" when no
// --variants was given.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.h"

namespace {
using namespace aovar::test;

TEST(EmptySelection, RulesThatDropEverythingAreBlamedNotVariants) {
  TempDir dir;
  const auto manifest = copy_shader_src(dir);
  // Every point has one of the two precisions: this rule alone drops the whole space.
  append_line(manifest, "\n[[rules]]\nskip = { precision = [\"highp\", \"mediump\"] }\nreason = \"drops everything\"\n");
  for (const std::string command : {"sweep", "measure"}) {
    const auto r = run_aovar(command + " --manifest " + manifest.string() + " --scene builtin:atrium --size 64x36 --out " +
                             (dir / ("out-" + command)).string());
    EXPECT_EQ(r.status, 2) << command << ": " << r.output;
    EXPECT_EQ(r.output.find("--variants"), std::string::npos) << command << ": " << r.output;
    EXPECT_NE(r.output.find("rule"), std::string::npos) << command << ": " << r.output;
  }
  // With a glob that matches nothing, the glob is named.
  const auto glob = run_aovar("measure --manifest " + (source_dir() / "shader_src" / "aovar.toml").string() +
                              " --variants 'nomethod-*' --scene builtin:atrium --size 64x36 --out " + (dir / "g").string());
  EXPECT_EQ(glob.status, 2) << glob.output;
  EXPECT_NE(glob.output.find("nomethod-*"), std::string::npos) << glob.output;
}

}  // namespace
