// Names that become paths stay inside the output folder (issue 20): the one check (util/path_names.h) and a
// views file whose view name climbs out of --out. The report's images: tests/report/test_report_paths.cpp;
// generate's --namespace: tests/compile/test_generate_names.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scene/scene.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/path_names.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

TEST(PathNames, OnlyPlainSingleComponentsPass) {
  for (const char* ok : {"overview", "closeup", "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp", "v_2.frag", "a+b=c,d@e"})
    EXPECT_EQ(util::path_component_problem(ok), "") << ok;
  for (const char* bad : {"", ".", "..", "../escaped/x", "/etc/x", "a/b", "a\\b", ".hidden", "-rf", "a b", "a\nb"})
    EXPECT_NE(util::path_component_problem(bad), "") << bad;
  EXPECT_NE(util::path_component_problem(std::string(201, 'a')), "");
  EXPECT_NE(util::path_component_problem(std::string("a\0b", 3)), "");
  const std::string m = thrown_message<std::runtime_error>([&] { util::check_path_component("../x\n", "view name"); });
  EXPECT_EQ(m.find('\n'), std::string::npos) << "one line: " << m;
  EXPECT_NE(m.find("view name '../x?'"), std::string::npos) << m;
}

TEST(PathNames, ContainedPathRefusesWhatResolvesOutside) {
  TempDir dir;
  fs::create_directories(dir / "out");
  fs::create_directories(dir / "elsewhere");
  fs::create_directory_symlink(dir / "elsewhere", dir / "out" / "link");
  EXPECT_EQ(util::contained_path(dir / "out", "images/a.png"), dir / "out" / "images/a.png");
  EXPECT_THROW(util::contained_path(dir / "out", "../elsewhere/a.png"), std::runtime_error);
  EXPECT_THROW(util::contained_path(dir / "out", "/tmp/a.png"), std::runtime_error);
  EXPECT_THROW(util::contained_path(dir / "out", "link/a.png"), std::runtime_error) << "through a symlink";
  EXPECT_TRUE(util::is_inside(dir / "out", dir / "out" / "x" / ".." / "y"));
  EXPECT_FALSE(util::is_inside(dir / "out", dir / "out"));
}

// Before: measure wrote OUT/../escaped/x.{pfm,png,stderr.pfm}. Now the views file is refused at its line.
TEST(PathNames, ViewNameThatLeavesTheOutputFolderIsRefused) {
  TempDir dir;
  for (const char* name : {"../escaped/x", "/tmp/aovar-absolute-view"}) {
    util::write_atomic(dir / "v.json", std::string("{\"views\": [\n  {\"name\": \"") + name +
                                           "\", \"eye\": [0, 1, 3], \"target\": [0, 0, 0]}\n]}\n");
    scene::LoadOptions o;
    o.views_file = dir / "v.json";
    const std::string m = thrown_message<std::runtime_error>([&] { scene::load_scene("builtin:stairs", o); });
    EXPECT_NE(m.find("v.json:2:"), std::string::npos) << "file and line: " << m;
    EXPECT_NE(m.find("view name"), std::string::npos) << m;
    auto r = run_aovar("reference --scene builtin:stairs --views-file " + (dir / "v.json").string() + " --rays 1 --size 8x8 --out " +
                       (dir / "out").string());
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("view name"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "escaped")) << "nothing written outside --out";
  EXPECT_FALSE(fs::exists("/tmp/aovar-absolute-view.pfm"));
}

}  // namespace
}  // namespace aovar::test
