#pragma once
// Internal to the glTF loader: the files a glTF names (buffers and images), checked before tinygltf reads
// any of them, and the tinygltf::FsCallbacks through which it reads them.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <tiny_gltf.h>

namespace aovar::scene::detail {

// A "uri" of the top-level "buffers" or "images" array, with a buffer's declared byteLength.
struct ResourceRef {
  bool image = false;
  std::size_t index = 0;
  std::string uri;  // empty for a data: URI or none (its bytes are in the file)
  std::optional<std::uint64_t> byte_length;
  std::string label() const;  // "buffer 0 'a.bin'"
};

// The references in a glTF's JSON text (a .gltf, or a .glb's JSON chunk); malformed JSON yields what was
// read before the error (check_json reports it).
std::vector<ResourceRef> resource_refs(std::string_view json);

// What tinygltf may read, once resource_refs passed the checks: the allowed paths, and the byte limit of
// one read. tinygltf gets callbacks that read only these (through util::read_file) and refuse the rest.
struct ResourceAccess {
  std::set<std::filesystem::path> files;
  std::uint64_t max_bytes = 0;
  std::string error;  // the first refusal, for the loader's message
};

// Applies the path policy (resolve_resource) to every reference, and refuses a buffer whose declared
// byteLength or file is larger than what is left of `limit` bytes (the memory for all buffers), naming
// `display` and the URI. Images are checked but never read (AO needs no textures).
ResourceAccess check_resources(const std::filesystem::path& scene_file, const std::string& display,
                               const std::vector<ResourceRef>& refs, std::uint64_t limit);

// tinygltf's file access bound to `access` (which must outlive the loader).
tinygltf::FsCallbacks fs_callbacks(ResourceAccess& access);

}  // namespace aovar::scene::detail
