// The glTF resource resolver (scene::resolve_resource, the path policy) and the reference collector and
// size checks around it. First byte even: the rest is one URI; odd: the rest is a glTF's JSON. Besides the
// usual findings, any path it accepts that lies outside the scene's folder (lexically or through the
// folder's symbolic links) is a finding.
#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include "fuzz_support.h"
#include "scene/gltf_resources.h"
#include "scene/resource_path.h"
#include "util/path_names.h"

namespace {
namespace fs = std::filesystem;

// scene/ with a file, a subfolder and two links out of it; outside.bin beside it. Made once per process and
// removed at exit (the path is never destroyed: the exit handler runs after static destructors would).
const fs::path& scene_folder() {
  static const fs::path* const folder = new fs::path([] {
    const fs::path root = fs::path(fs::exists("/dev/shm") ? "/dev/shm" : "/tmp") /
                          ("aovar-fuzz-" + std::to_string(getpid()) + "-resources");
    fs::create_directories(root / "scene/sub");
    std::ofstream(root / "outside.bin") << "outside";
    std::ofstream(root / "scene/a.bin") << "inside";
    std::ofstream(root / "scene/sub/b.bin") << "inside";
    std::error_code ec;
    fs::create_symlink("../outside.bin", root / "scene/out-link", ec);
    fs::create_symlink("..", root / "scene/dir-link", ec);
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(scene_folder().parent_path(), ignored);
    });
    return root / "scene";
  }());
  return *folder;
}

void expect_inside(const fs::path& p) {
  const fs::path rel = p.lexically_normal().lexically_relative(scene_folder().lexically_normal());
  if (rel.empty() || *rel.begin() == ".." || !aovar::util::is_inside(scene_folder(), p)) {
    std::fprintf(stderr, "finding: accepted %s, outside the scene's folder\n", p.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const fs::path scene = scene_folder() / "s.gltf";
  aovar::fuzz::expect_clean([&] {
    if (data[0] % 2 == 0) {
      if (aovar::scene::is_data_uri(text)) return;
      expect_inside(aovar::scene::resolve_resource(scene, "s.gltf", "buffer 0", text));
    } else {
      const auto access = aovar::scene::detail::check_resources(scene, "s.gltf",
                                                                aovar::scene::detail::resource_refs(text), 1u << 20);
      for (const fs::path& p : access.files) expect_inside(p);
    }
  });
  return 0;
}
