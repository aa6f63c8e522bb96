// Ray casting for choosing derived views: a median-split BVH over the triangles (see detail.h).
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/detail.h"

namespace aovar::scene::detail {

RayCaster::RayCaster(const Scene& scene) {
  const auto& n = scene.normals;
  const std::size_t count = scene.triangle_count();
  if (!scene.bounds.empty() && scene.bounds.diagonal() > 0.0f)
    centre_ = scene.bounds.center(), size_ = scene.bounds.diagonal();
  std::vector<Tri> tris(count);
  std::vector<glm::vec3> centroids(count);
  std::vector<std::uint32_t> order(count);
  auto unit = [&](std::uint32_t v) { return (scene.positions[v] - centre_) / size_; };
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t a = scene.indices[3 * i], b = scene.indices[3 * i + 1], c = scene.indices[3 * i + 2];
    const glm::vec3 pa = unit(a), pb = unit(b), pc = unit(c);
    tris[i] = {pa, pb - pa, pc - pa, n[a] + n[b] + n[c]};
    centroids[i] = (pa + pb + pc) / 3.0f;
    order[i] = static_cast<std::uint32_t>(i);
  }
  if (count == 0) return;
  nodes_.reserve(2 * count / 4 + 1);
  tris_ = std::move(tris);  // build() reads tris_ through `order`, then they are put in leaf order
  build(order, centroids, 0, static_cast<std::uint32_t>(count));
  std::vector<Tri> sorted(count);
  for (std::size_t i = 0; i < count; ++i) sorted[i] = tris_[order[i]];
  tris_ = std::move(sorted);
}

std::uint32_t RayCaster::build(std::vector<std::uint32_t>& order, const std::vector<glm::vec3>& centroids,
                               std::uint32_t begin, std::uint32_t end) {
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Bounds box, centres;
  for (std::uint32_t i = begin; i < end; ++i) {
    const Tri& t = tris_[order[i]];
    box.extend(t.v0), box.extend(t.v0 + t.e1), box.extend(t.v0 + t.e2);
    centres.extend(centroids[order[i]]);
  }
  nodes_[index].lo = box.min, nodes_[index].hi = box.max;
  if (end - begin <= 4) {
    nodes_[index].first = begin, nodes_[index].count = end - begin;
    return index;
  }
  const glm::vec3 extent = centres.max - centres.min;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  build(order, centroids, begin, mid);
  const std::uint32_t right = build(order, centroids, mid, end);
  nodes_[index].right = right;
  return index;
}

Hit RayCaster::cast(const glm::vec3& world_origin, const glm::vec3& d, float world_t_max) const {
  Hit best;
  if (nodes_.empty()) return best;
  const glm::vec3 o = (world_origin - centre_) / size_;
  const float t_max = world_t_max / size_;
  // Zero direction components are nudged so that no 0 * inf NaN reaches the slab comparisons.
  glm::vec3 inv;
  for (int k = 0; k < 3; ++k) inv[k] = 1.0f / (std::fabs(d[k]) > 1e-12f ? d[k] : std::copysign(1e-12f, d[k]));
  auto enter = [&](const Node& nd, float limit) {  // entry distance into the node's box, or -1
    glm::vec3 a = (nd.lo - o) * inv, b = (nd.hi - o) * inv;
    glm::vec3 lo = glm::min(a, b), hi = glm::max(a, b);
    float t0 = std::max({lo.x, lo.y, lo.z, 0.0f}), t1 = std::min({hi.x, hi.y, hi.z, limit});
    return t0 <= t1 * 1.0001f + 1e-6f ? t0 : -1.0f;
  };
  float t_best = t_max;
  const Tri* hit = nullptr;
  std::uint32_t stack[128];
  int top = 0;
  if (enter(nodes_[0], t_best) >= 0.0f) stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (nd.count > 0) {
      for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {  // Moeller-Trumbore, both sides
        const Tri& tri = tris_[i];
        glm::vec3 p = glm::cross(d, tri.e2);
        float det = glm::dot(tri.e1, p);
        if (std::fabs(det) < 1e-30f) continue;
        float inv_det = 1.0f / det;
        glm::vec3 s = o - tri.v0;
        float u = glm::dot(s, p) * inv_det;
        // A small barycentric margin: a ray through a shared edge hits one of its two triangles instead of
        // slipping through the crack, which rounding opens at one scale and not at another.
        constexpr float kEdge = 1e-5f;
        if (u < -kEdge || u > 1.0f + kEdge) continue;
        glm::vec3 q = glm::cross(s, tri.e1);
        float v = glm::dot(d, q) * inv_det;
        if (v < -kEdge || u + v > 1.0f + kEdge) continue;
        float t = glm::dot(tri.e2, q) * inv_det;
        if (t > 0.0f && t < t_best) t_best = t, hit = &tri;
      }
      continue;
    }
    const std::uint32_t left = static_cast<std::uint32_t>(&nd - nodes_.data()) + 1, right = nd.right;
    float tl = enter(nodes_[left], t_best), tr = enter(nodes_[right], t_best);
    // Push the farther child first so the nearer one is searched first and shrinks t_best.
    if (tl >= 0.0f && tr >= 0.0f) {
      bool left_first = tl <= tr;
      stack[top++] = left_first ? right : left;
      stack[top++] = left_first ? left : right;
    } else if (tl >= 0.0f) {
      stack[top++] = left;
    } else if (tr >= 0.0f) {
      stack[top++] = right;
    }
  }
  if (hit) best.t = t_best * size_, best.front = glm::dot(hit->n, d) <= 0.0f, best.normal = hit->n;
  return best;
}

float RayCaster::miss_share(const View& view, int cols, int rows, float aspect) const {
  const glm::vec3 f = glm::normalize(view.target - view.eye);
  const glm::vec3 r = glm::normalize(glm::cross(f, view.up)), u = glm::cross(r, f);
  const float ty = std::tan(glm::radians(view.fov_y_deg) * 0.5f), tx = ty * aspect;
  int misses = 0;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      float x = (2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(cols) - 1.0f) * tx;
      float y = (2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(rows) - 1.0f) * ty;
      misses += !cast(view.eye, glm::normalize(f + x * r + y * u), view.far_plane);
    }
  return static_cast<float>(misses) / static_cast<float>(cols * rows);
}

}  // namespace aovar::scene::detail
