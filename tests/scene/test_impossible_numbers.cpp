// Issue 34, impossible numbers in scenes and views: an overflowing number in a views file names the file and
// its position, path_frames states the real cap, and coordinates beyond what a float scene can hold (before or
// after @scale) name the scene and the vertex.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include "scene/scene.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

std::string views_error(const std::string& name, const std::string& text) {
  TempDir dir;
  test::write_text(dir / name, text);
  scene::LoadOptions o;
  o.views_file = dir / name;
  return test::thrown_message([&] { scene::load_scene("builtin:stairs", o); });
}

TEST(ImpossibleNumbers, ViewsFileOverflowNamesTheFileAndPosition) {
  for (const std::string number : {"1e400", "-1e400", "1E+999"}) {
    const std::string e = views_error("v.json", "{\"views\": [\n  {\"name\": \"a\", \"eye\": [1, 1, 1], \"target\": "
                                                "[0, 0, 0],\n   \"near\": " + number + "}]}");
    EXPECT_TRUE(test::is_one_line(e)) << e;
    EXPECT_TRUE(test::has_text(e, "v.json:3:")) << e;
    EXPECT_TRUE(test::has_text(e, number)) << e;
  }
  const std::string eye = views_error("v.json", R"({"views": [{"name": "a", "eye": [1e400, 1, 1], "target": [0, 0, 0]}]})");
  EXPECT_TRUE(test::has_text(eye, "v.json:1:")) << eye;
  const std::string toml = views_error("v.toml", "[[view]]\nname = \"a\"\neye = [1, 1, 1]\ntarget = [0, 0, 0]\nnear = 1e400\n");
  EXPECT_TRUE(test::is_one_line(toml) && test::has_text(toml, "v.toml:5:")) << toml;
}

TEST(ImpossibleNumbers, PathFramesStatesTheRealCap) {
  for (const std::string frames : {"100000000", "100001", "0", "-3"}) {
    const std::string e = views_error("v.toml", "[[view]]\nname = \"a\"\neye = [1, 1, 1]\ntarget = [0, 0, 0]\n"
                                                "path_frames = " + frames + "\n");
    EXPECT_TRUE(test::has_text(e, "v.toml:5:")) << e;
    EXPECT_TRUE(test::has_text(e, "'path_frames' must be a whole number from 1 to 100000")) << e;
  }
  EXPECT_EQ(views_error("v.toml", "[[view]]\nname = \"a\"\neye = [1, 1, 1]\ntarget = [0, 0, 0]\npath_frames = 100000\n"),
            "");
}

TEST(ImpossibleNumbers, HugeCoordinatesNameTheSceneAndTheVertex) {
  TempDir dir;
  const std::pair<std::string, std::string> cases[] = {{"v 1e19 0 0", "(1e+19, 0, 0)"},
                                                       {"v 0 -3e20 0", "(0, -3e+20, 0)"},
                                                       {"v 0 0 1e38", "(0, 0, 1e+38)"}};
  for (const auto& [line, shown] : cases) {
    test::write_text(dir / "far.obj", "v 0 0 0\nv 1 0 0\n" + line + "\nf 1 2 3\n");
    const std::string e = test::thrown_message([&] { scene::load_scene((dir / "far.obj").string()); });
    EXPECT_TRUE(test::is_one_line(e)) << e;
    EXPECT_TRUE(test::has_text(e, "far.obj: error: vertex 2 is at " + shown + ", beyond the 1e+18 world units")) << e;
  }
  // Within the limit, but not once scaled: the scaled coordinate is named.
  test::write_text(dir / "big.obj", "v 0 0 0\nv 1e13 0 0\nv 0 1e13 0\nf 1 2 3\n");
  EXPECT_EQ(test::thrown_message([&] { scene::load_scene((dir / "big.obj").string()); }), "");
  const std::string scaled = test::thrown_message([&] { scene::load_scene((dir / "big.obj").string() + "@scale=1e6"); });
  EXPECT_TRUE(test::has_text(scaled, "big.obj: error: vertex 1 is at (1e+19, 0, 0)")) << scaled;
}

}  // namespace
