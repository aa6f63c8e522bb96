#include "scene/tessellate.h"

#include <cstdint>
#include <limits>

#include <fmt/format.h>
#include <glm/glm.hpp>

namespace aovar::scene {
namespace {

// One level: each triangle (a, b, c) becomes the corner triangles and the middle one.
void split_once(Scene& s) {
  const std::size_t triangles = s.indices.size() / 3;
  std::vector<std::uint32_t> indices;
  indices.reserve(triangles * 12);
  s.positions.reserve(s.positions.size() + triangles * 3);
  s.normals.reserve(s.normals.size() + triangles * 3);
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    s.positions.push_back((s.positions[a] + s.positions[b]) * 0.5f);
    const glm::vec3 n = s.normals[a] + s.normals[b];  // zero stays zero (builtin:degenerate keeps such normals)
    s.normals.push_back(glm::dot(n, n) > 0.0f ? glm::normalize(n) : n);
    return static_cast<std::uint32_t>(s.positions.size() - 1);
  };
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t a = s.indices[3 * t], b = s.indices[3 * t + 1], c = s.indices[3 * t + 2];
    const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    indices.insert(indices.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  s.indices = std::move(indices);
}

}  // namespace

void tessellate(Scene& scene, int levels, const std::string& display) {
  std::size_t triangles = scene.indices.size() / 3, vertices = scene.positions.size();
  for (int l = 0; l < levels; ++l) {
    vertices += 3 * triangles;
    triangles *= 4;
  }
  if (triangles > kMaxTessellatedTriangles || vertices > std::numeric_limits<std::uint32_t>::max())
    throw SceneError(fmt::format("{}: error: tessellating {} times gives {} triangles, over the {} aovar renders "
                                 "(use a lower @tessellate=N)",
                                 display, levels, triangles, kMaxTessellatedTriangles));
  for (int l = 0; l < levels; ++l) split_once(scene);
}

}  // namespace aovar::scene
