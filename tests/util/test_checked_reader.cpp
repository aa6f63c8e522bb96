// Issue 34, inputs: the checked reader refuses what is not a regular file and what is too large, for every
// reader of a user-named file (templates, includes, views, scenes); impossible numbers get errors that name
// the file and the real limit; generate refuses an empty selection and removes nothing.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "compile/generate.h"
#include "scene/scene.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/progress.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

// A listening Unix socket at `path` (closed by the caller).
int make_socket(const fs::path& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", path.c_str());
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) ADD_FAILURE() << "bind " << path;
  return fd;
}

TEST(CheckedReader, RefusesEveryKindOfFileThatIsNotRegularNamingIt) {
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);  // opened without blocking: no writer ever comes
  const int sock = make_socket(dir / "sock");
  fs::create_directory(dir / "folder");
  fs::create_symlink("/dev/zero", dir / "zero-link");
  const std::pair<fs::path, const char*> cases[] = {{dir / "folder", "a directory"},   {"/dev/zero", "a character device"},
                                                    {"/dev/null", "a character device"}, {dir / "fifo", "a FIFO"},
                                                    {dir / "sock", "a socket"},          {dir / "zero-link", "a character device"}};
  for (const auto& [path, kind] : cases) {
    const std::string e = test::thrown_message([&] { util::read_file(path); });
    EXPECT_TRUE(one_line(e)) << path;
    EXPECT_TRUE(test::has_text(e, util::display_path(path) + ": error: cannot read: it is " + kind)) << e;
  }
  ::close(sock);
  EXPECT_FALSE(util::read_file(dir / "missing").has_value());  // missing stays "not there", for the caller
  write(dir / "ok.txt", "abc");
  EXPECT_EQ(util::read_file(dir / "ok.txt").value(), "abc");
}

TEST(CheckedReader, RefusesAFileOverTheLimitBeforeReadingIt) {
  TempDir dir;
  write(dir / "small", std::string(100, 'x'));
  EXPECT_EQ(util::read_file(dir / "small", 100).value().size(), 100u);
  const std::string e = test::thrown_message([&] { util::read_file(dir / "small", 99); });
  EXPECT_TRUE(test::has_text(e, "small: error: cannot read: 100 bytes is more than the limit of 99 bytes")) << e;
  // A sparse file just over the default limit: refused from its size alone (reading it would take 2 GiB).
  { std::ofstream(dir / "sparse"); }
  fs::resize_file(dir / "sparse", util::kMaxReadBytes + 1);
  const std::string big = test::thrown_message([&] { util::read_file(dir / "sparse"); });
  EXPECT_TRUE(test::has_text(big, "sparse: error: cannot read: 2048.0 MiB is more than the limit of 2048.0 MiB")) << big;
}

fs::path default_manifest() { return test::source_dir() / "shader_src/aovar.toml"; }

compile::CompileOptions one_variant() {
  compile::CompileOptions o;
  o.targets = {variants::Target::vulkan};
  o.globs = {"alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp"};
  return o;
}

TEST(CheckedReader, TemplateAndIncludeThatAreNotFilesNameTheirLine) {
  TempDir dir;
  const fs::path manifest = test::copy_shader_src(dir);
  const fs::path alchemy = dir / "shader_src/ao/alchemy.glsl";
  const std::string original = util::read_file(alchemy).value();
  const int last = static_cast<int>(std::count(original.begin(), original.end(), '\n')) + 1;
  ASSERT_EQ(::mkfifo((dir / "shader_src/common/fifo.glsl").c_str(), 0644), 0);
  const std::pair<std::string, std::string> includes[] = {
      {"common", "shader_src/common: it is a directory"},  // an #include of a directory was read as empty text
      {"../common/", "shader_src/common/: it is a directory"},
      {"/dev/zero", "/dev/zero: it is a character device"},
      {"common/fifo.glsl", "common/fifo.glsl: it is a FIFO"}};
  for (const auto& [target, why] : includes) {
    util::write_atomic(alchemy, original + "#include \"" + target + "\"\n");
    const std::string e = test::thrown_message([&] { compile::plan_space(manifest, one_variant()); });
    EXPECT_TRUE(one_line(e)) << target << ": " << e;
    EXPECT_TRUE(test::has_text(e, "alchemy.glsl:" + std::to_string(last) + ": error: #include \"" + target + "\" names "))
        << e;
    EXPECT_TRUE(test::has_text(e, why)) << e;
  }
  util::write_atomic(alchemy, original);
  test::replace_in_file(manifest, "template = \"ao/{depth_mip}/{algorithm}.glsl\"", "template = \"/dev/zero\"");
  const std::string e = test::thrown_message([&] { compile::plan_space(manifest, one_variant()); });
  EXPECT_TRUE(test::has_text(e, "aovar.toml:")) << e;
  EXPECT_TRUE(test::has_text(e, "error: template '/dev/zero' (/dev/zero): it is a character device")) << e;
}

TEST(CheckedReader, SceneAndViewsFilesThatAreNotFilesAreNamed) {
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "s.obj").c_str(), 0644), 0);
  fs::create_directory(dir / "d.gltf");
  const std::pair<fs::path, const char*> scenes[] = {{dir / "s.obj", "a FIFO"}, {dir / "d.gltf", "a directory"}};
  for (const auto& [path, kind] : scenes) {
    const std::string e = test::thrown_message([&] { scene::load_scene(path.string()); });
    EXPECT_TRUE(test::has_text(e, util::display_path(path) + ": error: cannot read: it is " + kind)) << e;
  }
  for (const fs::path& views : {fs::path("/dev/zero"), dir / "d.gltf", dir / "s.obj"}) {
    scene::LoadOptions o;
    o.views_file = views;
    std::string e;
    try {
      scene::load_scene("builtin:stairs", o);
    } catch (const scene::SceneError& error) {  // the scene's own error type, as for any views problem
      e = error.what();
    }
    EXPECT_TRUE(test::has_text(e, util::display_path(views) + ": error: cannot read: it is ")) << e;
  }
}

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
    const auto r = test::run_aovar("generate --manifest " + default_manifest().string() + " " + globs + " --out " +
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

std::string views_error(const std::string& name, const std::string& text) {
  TempDir dir;
  write(dir / name, text);
  scene::LoadOptions o;
  o.views_file = dir / name;
  return test::thrown_message([&] { scene::load_scene("builtin:stairs", o); });
}

TEST(ImpossibleNumbers, ViewsFileOverflowNamesTheFileAndPosition) {
  for (const std::string number : {"1e400", "-1e400", "1E+999"}) {
    const std::string e = views_error("v.json", "{\"views\": [\n  {\"name\": \"a\", \"eye\": [1, 1, 1], \"target\": "
                                                "[0, 0, 0],\n   \"near\": " + number + "}]}");
    EXPECT_TRUE(one_line(e)) << e;
    EXPECT_TRUE(test::has_text(e, "v.json:3:")) << e;
    EXPECT_TRUE(test::has_text(e, number)) << e;
  }
  const std::string eye = views_error("v.json", R"({"views": [{"name": "a", "eye": [1e400, 1, 1], "target": [0, 0, 0]}]})");
  EXPECT_TRUE(test::has_text(eye, "v.json:1:")) << eye;
  const std::string toml = views_error("v.toml", "[[view]]\nname = \"a\"\neye = [1, 1, 1]\ntarget = [0, 0, 0]\nnear = 1e400\n");
  EXPECT_TRUE(one_line(toml) && test::has_text(toml, "v.toml:5:")) << toml;
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
    write(dir / "far.obj", "v 0 0 0\nv 1 0 0\n" + line + "\nf 1 2 3\n");
    const std::string e = test::thrown_message([&] { scene::load_scene((dir / "far.obj").string()); });
    EXPECT_TRUE(one_line(e)) << e;
    EXPECT_TRUE(test::has_text(e, "far.obj: error: vertex 2 is at " + shown + ", beyond the 1e+18 world units")) << e;
  }
  // Within the limit, but not once scaled: the scaled coordinate is named.
  write(dir / "big.obj", "v 0 0 0\nv 1e13 0 0\nv 0 1e13 0\nf 1 2 3\n");
  EXPECT_EQ(test::thrown_message([&] { scene::load_scene((dir / "big.obj").string()); }), "");
  const std::string scaled = test::thrown_message([&] { scene::load_scene((dir / "big.obj").string() + "@scale=1e6"); });
  EXPECT_TRUE(test::has_text(scaled, "big.obj: error: vertex 1 is at (1e+19, 0, 0)")) << scaled;
}

TEST(ImpossibleNumbers, AHugeProgressIntervalMeansNoLinesNotALineEveryUpdate) {
  for (const double interval : {1e10, 1e300, 5.0}) {
    std::ostringstream out;
    util::ProgressReporter p(out, false, interval);
    p.update("a");
    p.update("b");
    EXPECT_EQ(out.str(), "") << interval;  // before the fix 1e10 s overflowed the clock to 0
  }
}

}  // namespace
