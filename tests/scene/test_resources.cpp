// Issue 34, paths and sizes: a glTF names its buffers and images beside it or below it (scene::resolve_resource,
// the one path policy), and a buffer's declared and real sizes are checked before tinygltf reads a byte.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>

#include "scene/gltf_resources.h"
#include "scene/resource_path.h"
#include "scene/scene.h"
#include "test_support.h"
#include "util/path_names.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

// One triangle's positions (36 bytes, floats) as a .bin.
std::string triangle_bin() {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

// A .gltf whose one buffer has `uri` and `byte_length`, and an image with `image_uri` when given.
std::string gltf_naming(const std::string& uri, std::uint64_t byte_length = 36, const std::string& image_uri = "") {
  std::string images = image_uri.empty() ? "" : R"(, "images": [{"uri": ")" + image_uri + R"("}])";
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
  "buffers": [{"byteLength": )" +
         std::to_string(byte_length) + R"(, "uri": ")" + uri + R"("}])" + images + "}";
}

std::string gltf_load_error(const fs::path& gltf, std::uint64_t memory_limit = 64u << 20) {
  scene::LoadOptions o;
  o.memory_limit = memory_limit;
  return test::thrown_message([&] { scene::load_scene(gltf.string(), o); });
}

TEST(ScenePaths, BuffersBesideOrBelowTheSceneLoad) {
  TempDir dir;
  test::write_text(dir / "scene/tri.bin", triangle_bin());
  test::write_text(dir / "scene/sub/deep/tri.bin", triangle_bin());
  test::write_text(dir / "scene/my tri.bin", triangle_bin());
  for (const std::string uri : {"tri.bin", "./tri.bin", "sub/deep/tri.bin", "sub/./deep/tri.bin", "my%20tri.bin",
                                "my+tri.bin", "sub/deep/..tri.bin.missing"}) {
    test::write_text(dir / "scene/s.gltf", gltf_naming(uri));
    const std::string e = gltf_load_error(dir / "scene/s.gltf");
    if (uri.ends_with(".missing"))  // ".." inside a name is not a segment: allowed, and then not found
      EXPECT_TRUE(test::has_text(e, "cannot open")) << e;
    else
      EXPECT_EQ(e, "") << uri;
  }
  // Through a relative scene path, and a data: URI (no file at all).
  test::write_text(dir / "scene/s.gltf", gltf_naming("tri.bin"));
  EXPECT_EQ(gltf_load_error(fs::relative(dir / "scene/s.gltf")), "");
  test::write_text(dir / "scene/inline.gltf",
        gltf_naming("data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"));
  EXPECT_EQ(gltf_load_error(dir / "scene/inline.gltf"), "");
}

TEST(ScenePaths, EveryWayOutOfTheFolderIsRefusedNamingSceneAndUri) {
  TempDir dir;
  test::write_text(dir / "outside.bin", triangle_bin());
  test::write_text(dir / "scene/tri.bin", triangle_bin());
  fs::create_symlink("../outside.bin", dir / "scene/link.bin");
  fs::create_symlink(dir.path(), dir / "scene/linkdir");
  const std::pair<std::string, std::string> cases[] = {
      {"../outside.bin", "'..' segment"},
      {"sub/../../outside.bin", "'..' segment"},
      {"tri.bin/../../outside.bin", "'..' segment"},
      {"/etc/passwd", "absolute path"},
      {"//etc/passwd", "absolute path"},
      {"file:///etc/passwd", "scheme"},
      {"file:tri.bin", "scheme"},
      {"FILE:/etc/passwd", "scheme"},
      {"http://example.com/x.bin", "scheme"},
      {"C:/x.bin", "scheme or drive"},
      {"%2e%2e/outside.bin", "encodes '.' as %2e"},
      {"%2E%2E%2Foutside.bin", "encodes '.' as %2E"},
      {"..%2foutside.bin", "encodes '/' as %2f"},
      {"..%5Coutside.bin", "encodes '\\' as %5C"},
      {"%252e%252e/outside.bin", "encodes '%' as %25"},
      {"tri.bin%00", "encodes byte 0"},
      {"tri.bin%zz", "malformed percent-escape"},
      {"tri.bin%2", "malformed percent-escape"},
      {"..\\\\outside.bin", "backslash"},
      {"sub\\\\..\\\\..\\\\outside.bin", "backslash"},
      {"link.bin", "symbolic link takes it outside"},
      {"linkdir/outside.bin", "symbolic link takes it outside"},
      {".", "names a folder"},
      {"sub/", "names a folder"},
  };
  for (const auto& [uri, why] : cases) {
    test::write_text(dir / "scene/s.gltf", gltf_naming(uri));
    const std::string e = gltf_load_error(dir / "scene/s.gltf");
    EXPECT_TRUE(test::has_text(e, "s.gltf: error: buffer 0 '")) << uri << ": " << e;
    EXPECT_TRUE(test::has_text(e, why)) << uri << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  // An image is never read (AO needs no texture), but the same policy holds for it.
  test::write_text(dir / "scene/s.gltf", gltf_naming("tri.bin", 36, "../secret.png"));
  const std::string image = gltf_load_error(dir / "scene/s.gltf");
  EXPECT_TRUE(test::has_text(image, "s.gltf: error: image 0 '../secret.png' is refused: it has a '..' segment")) << image;
  test::write_text(dir / "scene/s.gltf", gltf_naming("tri.bin", 36, "textures/missing.png"));
  EXPECT_EQ(gltf_load_error(dir / "scene/s.gltf"), "");
}

TEST(ScenePaths, ResolverKeepsEveryAcceptedPathInsideTheFolder) {
  TempDir dir;
  const fs::path scene = dir / "s.gltf";
  for (const std::string uri : {"a.bin", "x/y/z.bin", "a%20b.bin", "a..b.bin", "...bin", "x//y.bin"}) {
    const fs::path p = scene::resolve_resource(scene, "s.gltf", "buffer 0", uri);
    EXPECT_TRUE(util::is_inside(dir.path(), p)) << uri << " -> " << p;
  }
  EXPECT_EQ(scene::resolve_resource(scene, "s.gltf", "buffer 0", "a%20b+c.bin"), dir / "a b c.bin");
  EXPECT_TRUE(scene::is_data_uri("DATA:application/octet-stream;base64,AA=="));
  EXPECT_FALSE(scene::is_data_uri("data.bin"));
}

// The refs a .gltf names, read without a document: an element of buffers or images that is no object (the
// malformed `"images": [["uri", ...]]`, a fuzz finding that read refs.back() of an empty list) names none,
// and the object elements around it keep their indices.
TEST(SceneBuffers, OnlyObjectElementsOfBuffersAndImagesNameResources) {
  const auto refs = scene::detail::resource_refs(
      R"({"buffeRs": [{"uri": "4,AAAA"}], "images": [["uri", 3, "b.png"], {"uri": "a.png"}],)"
      R"( "buffers": [{"byteLength": 6, "uri": "a.bin"}, [{"uri": "deep.bin"}]]})");
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_TRUE(refs[0].image);
  EXPECT_EQ(refs[0].uri, "a.png");
  EXPECT_EQ(refs[0].index, 0u) << "the array element is not counted: tinygltf has no image there either";
  EXPECT_FALSE(refs[1].image);
  EXPECT_EQ(refs[1].uri, "a.bin");
  EXPECT_EQ(refs[1].byte_length, 6u);
  // Cut off inside such an element, as the finding was: no ref, no crash.
  EXPECT_TRUE(scene::detail::resource_refs(R"({"buffeRs": [{"uri": "4,AAAA"}], "images": [["uri":})").empty());
}

TEST(SceneBuffers, DeclaredAndRealSizesAreCheckedBeforeReading) {
  TempDir dir;
  test::write_text(dir / "s/tri.bin", triangle_bin());
  // A 50 GB sparse file whose byteLength claims 36 bytes: refused from its size, never read.
  { std::ofstream(dir / "s/huge.bin"); }
  fs::resize_file(dir / "s/huge.bin", 50'000'000'000ull);
  test::write_text(dir / "s/a.gltf", gltf_naming("huge.bin"));
  std::string e = gltf_load_error(dir / "s/a.gltf");
  EXPECT_TRUE(test::has_text(e, "a.gltf: error: buffer 0 'huge.bin': is a file of 46.6 GiB, more than the")) << e;
  // A byteLength of 50 GB on a small file.
  test::write_text(dir / "s/a.gltf", gltf_naming("tri.bin", 50'000'000'000ull));
  e = gltf_load_error(dir / "s/a.gltf");
  EXPECT_TRUE(test::has_text(e, "a.gltf: error: buffer 0 'tri.bin': declares a byteLength of 46.6 GiB")) << e;
  // Two buffers that fit alone but not together.
  { std::ofstream(dir / "s/40m.bin"); }
  fs::resize_file(dir / "s/40m.bin", 40u << 20);
  std::string two = gltf_naming("40m.bin", 40u << 20);
  const std::size_t buffers = two.find("\"buffers\": [") + 12;
  two.insert(buffers, R"({"byteLength": 41943040, "uri": "40m.bin"}, )");
  test::write_text(dir / "s/two.gltf", two);
  e = gltf_load_error(dir / "s/two.gltf");
  EXPECT_TRUE(test::has_text(e, "two.gltf: error: buffer 1 '40m.bin'")) << e;
  // A FIFO and a directory named as buffers: the checked reader refuses them without blocking.
  ASSERT_EQ(::mkfifo((dir / "s/fifo.bin").c_str(), 0644), 0);
  test::write_text(dir / "s/a.gltf", gltf_naming("fifo.bin"));
  e = gltf_load_error(dir / "s/a.gltf");
  EXPECT_TRUE(test::has_text(e, "a.gltf: error: cannot read a buffer:") && test::has_text(e, "it is a FIFO")) << e;
}

}  // namespace
