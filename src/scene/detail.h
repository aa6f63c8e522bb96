#pragma once
// Internal to the scene module: helpers shared by the loaders, the built-in scenes and the view code.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"
#include "util/text.h"

namespace aovar::scene::detail {

// Throws SceneError with `message` collapsed to one line (newlines and runs of blanks become one space).
[[noreturn]] void fail(std::string_view message);
using util::one_line;  // util/text.h
std::string format_bytes(std::uint64_t bytes);  // "12.3 MiB"

// Bytes a scene may take: options.memory_limit, or half of MemAvailable when it is 0.
std::uint64_t memory_limit(const LoadOptions& options);
// Refuses (SceneError) when `estimate` exceeds `limit`; `what` says what was estimated from what.
void check_memory(const std::string& display, std::uint64_t estimate, std::uint64_t limit, std::string_view what);
// Bytes of the finished scene (positions, normals, indices) and the guard on absurd sizes (indices are u32).
std::uint64_t scene_bytes(std::uint64_t vertices, std::uint64_t indices);
inline constexpr std::uint64_t kMaxTriangles = 200'000'000;  // ~5 GB as a Scene; beyond is a broken file
void check_size(const std::string& display, std::uint64_t vertices, std::uint64_t indices, const LoadOptions& options);

// Unit vector, or `fallback` when `v` is zero, tiny or not finite.
glm::vec3 safe_normalize(const glm::vec3& v, const glm::vec3& fallback);

// Area-weighted smooth normals per position (triangle list `indices` into `positions`). A vertex whose
// face normals cancel or are all degenerate takes its largest adjacent face's normal, then +Y: never NaN.
std::vector<glm::vec3> smooth_normals(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);

// Crease angle for normals computed where a file has none: faces meeting at a sharper edge keep their
// own normals (a box's 90-degree corners), gentler ones blend (scans, tessellated curves). 60 degrees is
// Unity's default "Smoothing Angle" for calculated normals; Blender's auto smooth defaults to 30 and
// assimp's GenSmoothNormals to 175 (no creases), but 30 splits noisy scan vertices and 175 is the
// cross-edge smoothing this replaces. Any value between the scans' spread and 90 splits boxes.
inline constexpr float kCreaseAngleDeg = 60.0f;
// A position with more faces than this (a huge fan) skips the pairwise crease test, which is quadratic in
// its face count, and keeps the plain smooth normal.
inline constexpr std::size_t kMaxCreaseFan = 4096;

// One unit normal per corner of the triangle list: the area-weighted sum of the normals of the faces
// around its position whose normal is within `crease_deg` of its own face's normal. Corners of degenerate
// faces take smooth_normals' result for their position (and its fallbacks): never NaN.
std::vector<glm::vec3> crease_normals(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                      float crease_deg = kCreaseAngleDeg);
// Gives each vertex from `first_vertex` on with a zero normal the normal of the corners that use it
// (corner k is scene.indices[first_index + k]); where its corners need different normals, the vertex is
// copied (same position, own normal, appended) and those corners re-pointed. Vertices with a normal, and
// those before first_vertex, are left as they are.
void assign_corner_normals(Scene& scene, std::size_t first_vertex, std::size_t first_index,
                           std::span<const glm::vec3> corner_normals);

// The largest |coordinate| finalize accepts: squared distances of the bounds stay finite in float.
inline constexpr float kMaxCoordinate = 1e18f;

// Checks indices and positions (finite, within kMaxCoordinate), renormalises normals (fallback +Y) unless `keep_normals`, computes bounds
// and the content hash.
void finalize(Scene& scene, const std::string& display, bool keep_normals = false);

// Loaders. `display` is the path as shown in messages. They fill the geometry and mesh_count.
Scene load_obj(const std::filesystem::path& path, const std::string& display, const LoadOptions& options);
Scene load_gltf(const std::filesystem::path& path, const std::string& display, const LoadOptions& options, bool binary);
// `name` without the "builtin:" prefix. Fills geometry, views and ao_radius; throws for unknown names.
Scene make_builtin(std::string_view name);
std::vector<std::string> builtin_names();  // without the prefix
// Whether load_scene keeps a built-in scene's normals as built: builtin:degenerate's zero-length normals
// are its point (a stress scene), so they are not repaired.
bool builtin_keeps_normals(std::string_view name);

// Views.
// Sets far to just beyond the farthest corner of `bounds` seen from the eye anywhere on its path (so all of
// the scene fits) and near to `near`.
void fit_planes(View& view, const Bounds& bounds, float near);
std::vector<View> derive_views(const Scene& scene);  // overview, closeup, background from the geometry
// Reads a TOML or JSON views file (format: views.cpp) and merges it into scene.views: its views replace
// the same-named ones, the rest are appended (overview, closeup, background stay first). Near and far
// planes the file leaves out are fitted to the scene's bounds.
// `scale` multiplies the file's lengths (a scene loaded with "@scale=F").
void apply_views_file(Scene& scene, const std::filesystem::path& path, float scale = 1.0f);
void scale_view(View& v, float f);  // eye, target, planes, path offset times f

// Ray casting against the scene's triangles through a small median-split BVH: derived views are chosen
// with a few thousand rays, which brute force would make cost seconds on the 200k-triangle dragon.
// It works in the scene's unit box (centre at 0, diagonal 1), so that its tolerances are shares of the
// scene and a scaled scene picks the same views (docs/scale.md).
struct Hit {
  float t = -1.0f;         // distance along the (unit) direction; < 0: miss
  bool front = true;       // the ray meets the side the vertex normals point to
  glm::vec3 normal{0.0f};  // the triangle's summed vertex normals (not normalised)
  explicit operator bool() const { return t >= 0.0f; }
};
class RayCaster {
 public:
  explicit RayCaster(const Scene& scene);
  Hit cast(const glm::vec3& origin, const glm::vec3& dir, float t_max = 1e30f) const;
  // Share of a grid of primary rays (cols x rows over the view's frustum at `aspect`) that hit nothing
  // nearer than the far plane.
  float miss_share(const View& view, int cols = 16, int rows = 9, float aspect = 16.0f / 9.0f) const;

 private:
  struct Tri {
    glm::vec3 v0, e1, e2, n;  // n: sum of the vertex normals (orientation only)
  };
  struct Node {
    glm::vec3 lo, hi;
    std::uint32_t first = 0, count = 0;  // leaf: tris_[first, first + count); inner: count 0
    std::uint32_t right = 0;             // inner: the left child is the next node
  };
  std::uint32_t build(std::vector<std::uint32_t>& order, const std::vector<glm::vec3>& centroids, std::uint32_t begin,
                      std::uint32_t end);
  std::vector<Tri> tris_;
  std::vector<Node> nodes_;
  glm::vec3 centre_{0.0f};  // world = unit * size_ + centre_
  float size_ = 1.0f;
};

}  // namespace aovar::scene::detail
