// The glTF 2.0 loader: .glb when the input starts with the binary container's magic, else .gltf text.
#include "fuzz_support.h"
#include "scene/detail.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const char* name = binary ? "scene.glb" : "scene.gltf";
  const auto path = aovar::fuzz::input_file(data, size, name);
  aovar::scene::LoadOptions options;
  options.memory_limit = 256u << 20;
  aovar::fuzz::expect_clean([&] { aovar::scene::detail::load_gltf(path, name, options, binary); });
  return 0;
}
