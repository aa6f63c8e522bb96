// The views-file parser, TOML and JSON (the first non-space byte picks which, as the file name would).
#include <cctype>

#include "fuzz_support.h"
#include "scene/detail.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const aovar::scene::Scene base = aovar::scene::load_scene("builtin:stairs");
  std::size_t first = 0;
  while (first < size && std::isspace(data[first])) ++first;
  const bool json = first < size && (data[first] == '{' || data[first] == '[');
  const auto path = aovar::fuzz::input_file(data, size, json ? "views.json" : "views.toml");
  aovar::fuzz::expect_clean([&] {
    aovar::scene::Scene scene = base;
    aovar::scene::detail::apply_views_file(scene, path);
  });
  return 0;
}
