#pragma once
// Scenes: triangle geometry in world space (all meshes merged, node transforms applied), its bounds and
// content hash, and named camera views. Loaded from Wavefront OBJ, glTF 2.0 (.gltf/.glb) or built in
// ("builtin:atrium" and friends, procedural, no files). AO needs no materials, so none are kept.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace aovar::scene {

// One line, ready for stderr: "path:line: error: what (what to do)" or "path: offset N: error: ...".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{std::numeric_limits<float>::lowest()};
  void extend(const glm::vec3& p) { min = glm::min(min, p); max = glm::max(max, p); }
  bool empty() const { return min.x > max.x; }
  glm::vec3 center() const { return 0.5f * (min + max); }
  float diagonal() const { return empty() ? 0.0f : glm::length(max - min); }
};

// A named camera. The camera path for progressive variants and flicker: over `path_frames` frames the eye
// and the target move linearly by `path_offset` (zero offset = static camera).
struct View {
  std::string name;
  glm::vec3 eye{0.0f, 0.0f, 1.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y_deg = 60.0f;  // vertical field of view
  float near_plane = 0.1f;
  float far_plane = 100.0f;
  glm::vec3 path_offset{0.0f};
  int path_frames = 8;
};

// Eye and target of frame `frame` (0-based, clamped to the path) of a view's camera path.
struct CameraPose {
  glm::vec3 eye, target, up;
};
CameraPose camera_at(const View& view, int frame);

// Every field of a view (name, camera, planes, path) as text: what caches key a view by.
std::string camera_text(const View& view);

struct Scene {
  std::string name;    // "builtin:atrium", or the file path as given
  std::string source;  // "builtin" or the file's display path
  std::vector<glm::vec3> positions;  // world space
  // World space, unit length (smooth normals computed when absent); only the stress scene
  // builtin:degenerate keeps zero-length normals on purpose.
  std::vector<glm::vec3> normals;
  std::vector<std::uint32_t> indices;  // triangle list
  int mesh_count = 0;                  // meshes (OBJ shapes, glTF primitives, built-in parts) merged
  Bounds bounds;
  std::string content_hash;  // of the geometry (positions, normals, indices): identifies the scene in caches
  float ao_radius = 0.0f;    // default world-space AO radius for this scene
  std::vector<View> views;   // at least: overview, closeup, background (in this order)

  std::size_t triangle_count() const { return indices.size() / 3; }
  // Throws SceneError listing the available views.
  const View& view(std::string_view name) const;
};

struct LoadOptions {
  // Views side file (TOML or JSON). Empty: "<scene>.views.toml" or "<scene>.views.json" next to a file
  // scene when present, else views derived from the bounding box.
  std::filesystem::path views_file;
  // Refuse scenes whose estimated in-memory size exceeds this many bytes (0 = half of available memory).
  std::uint64_t memory_limit = 0;
};

// "SPEC@scale=F" loads SPEC with every length times F (geometry, views, the built-in radius): the same
// scene in other units, which every result must survive (docs/scale.md).
inline constexpr std::string_view kScaleSuffix = "@scale=";
// "SPEC@tessellate=N" (N from 1 to 4) splits every triangle into 4^N (scene/tessellate.h): the same surface with
// more triangles, for measuring what geometry costs. Both suffixes may follow SPEC, in either order.
inline constexpr std::string_view kTessellateSuffix = "@tessellate=";

// "builtin:<name>" or a path to .obj/.gltf/.glb, optionally with kScaleSuffix and kTessellateSuffix. Throws SceneError (one line, naming the file, the line
// or byte offset, and what to do) for unknown names, missing, broken, empty or too-large files.
Scene load_scene(const std::string& spec, const LoadOptions& options = {});

std::vector<std::string> builtin_scene_names();  // "builtin:atrium", "builtin:spheres", ...
inline constexpr std::string_view kDefaultScene = "builtin:atrium";

}  // namespace aovar::scene
