// Issue 34, inputs: the checked reader refuses what is not a regular file and what is too large, for every
// reader of a user-named file (templates, includes, views, scenes). Impossible numbers:
// tests/scene/test_impossible_numbers.cpp; generate's empty selection: tests/compile/test_generate_selection.cpp.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <fstream>

#include "compile/generate.h"
#include "scene/scene.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

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
    EXPECT_TRUE(test::is_one_line(e)) << path;
    EXPECT_TRUE(test::has_text(e, util::display_path(path) + ": error: cannot read: it is " + kind)) << e;
  }
  ::close(sock);
  EXPECT_FALSE(util::read_file(dir / "missing").has_value());  // missing stays "not there", for the caller
  test::write_text(dir / "ok.txt", "abc");
  EXPECT_EQ(util::read_file(dir / "ok.txt").value(), "abc");
}

TEST(CheckedReader, RefusesAFileOverTheLimitBeforeReadingIt) {
  TempDir dir;
  test::write_text(dir / "small", std::string(100, 'x'));
  EXPECT_EQ(util::read_file(dir / "small", 100).value().size(), 100u);
  const std::string e = test::thrown_message([&] { util::read_file(dir / "small", 99); });
  EXPECT_TRUE(test::has_text(e, "small: error: cannot read: 100 bytes is more than the limit of 99 bytes")) << e;
  // A sparse file just over the default limit: refused from its size alone (reading it would take 2 GiB).
  { std::ofstream(dir / "sparse"); }
  fs::resize_file(dir / "sparse", util::kMaxReadBytes + 1);
  const std::string big = test::thrown_message([&] { util::read_file(dir / "sparse"); });
  EXPECT_TRUE(test::has_text(big, "sparse: error: cannot read: 2048.0 MiB is more than the limit of 2048.0 MiB")) << big;
}

compile::CompileOptions one_variant() {
  compile::CompileOptions o;
  o.scope.targets = {variants::Target::vulkan};
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
    const std::string e = test::thrown_message([&] { compile::plan_space(aovar::test::on_manifest(one_variant(), manifest)); });
    EXPECT_TRUE(test::is_one_line(e)) << target << ": " << e;
    EXPECT_TRUE(test::has_text(e, "alchemy.glsl:" + std::to_string(last) + ": error: #include \"" + target + "\" names "))
        << e;
    EXPECT_TRUE(test::has_text(e, why)) << e;
  }
  util::write_atomic(alchemy, original);
  test::replace_in_file(manifest, "template = \"ao/{depth_mip}/{algorithm}.glsl\"", "template = \"/dev/zero\"");
  const std::string e = test::thrown_message([&] { compile::plan_space(aovar::test::on_manifest(one_variant(), manifest)); });
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

}  // namespace
