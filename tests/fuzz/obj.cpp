// The OBJ loader (tinyobjloader, then aovar's checks, triangulation and normals), with a memory limit as
// a user would set one, so that a size check and not the fuzzer's RSS limit has to stop a huge file.
#include "fuzz_support.h"
#include "scene/detail.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = aovar::fuzz::input_file(data, size, "scene.obj");
  aovar::scene::LoadOptions options;
  options.memory_limit = 256u << 20;
  aovar::fuzz::expect_clean([&] { aovar::scene::detail::load_obj(path, "scene.obj", options); });
  return 0;
}
