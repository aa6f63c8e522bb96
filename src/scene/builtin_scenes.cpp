// Procedural scenes (no files): Y up, metres. Flat pieces (boxes, steps, walls) get per-face normals with
// duplicated vertices at hard edges; curved ones (columns, spheres, arch soffits) smooth analytic normals.
// Every triangle is wound counter-clockwise seen from the side its normals point to. Contacts are exact:
// spheres touch their support at the pole vertex, columns stand on their plinths, steps on the floor.
#include <cmath>
#include <functional>
#include <numbers>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/detail.h"

namespace aovar::scene::detail {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

class Builder {
 public:
  explicit Builder(Scene& s) : s_(s) {}

  // Applies to the pieces added until the next call (positions by `m`, normals by its inverse transpose).
  void transform(const glm::mat4& m) {
    m_ = m;
    n_ = glm::transpose(glm::inverse(glm::mat3(m)));
  }
  void identity() { transform(glm::mat4(1.0f)); }

  std::uint32_t vertex(const glm::vec3& p, const glm::vec3& n) {
    s_.positions.push_back(glm::vec3(m_ * glm::vec4(p, 1.0f)));
    s_.normals.push_back(glm::normalize(n_ * n));
    return static_cast<std::uint32_t>(s_.positions.size() - 1);
  }

  // Winds the triangle so that it faces the way its vertex normals point.
  void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const auto& p = s_.positions;
    glm::vec3 g = glm::cross(p[b] - p[a], p[c] - p[a]);
    glm::vec3 n = s_.normals[a] + s_.normals[b] + s_.normals[c];
    if (glm::dot(g, n) < 0.0f) std::swap(b, c);
    s_.indices.insert(s_.indices.end(), {a, b, c});
  }
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) { tri(a, b, c), tri(a, c, d); }

  // The raw path of builtin:degenerate: the normal is stored as given (transformed, not normalised, so a
  // zero normal stays zero), and the triangle keeps the given winding (tri() orients by the normals, which
  // a zero normal or a zero-area triangle cannot tell).
  std::uint32_t raw_vertex(const glm::vec3& p, const glm::vec3& n) {
    s_.positions.push_back(glm::vec3(m_ * glm::vec4(p, 1.0f)));
    s_.normals.push_back(n_ * n);
    return static_cast<std::uint32_t>(s_.positions.size() - 1);
  }
  void raw_tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) { s_.indices.insert(s_.indices.end(), {a, b, c}); }
  void mesh() { ++s_.mesh_count; }

  // Planar convex quad p0..p3 (in order around it) facing `outward`.
  void flat_quad(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
                 const glm::vec3& outward) {
    quad(vertex(p0, outward), vertex(p1, outward), vertex(p2, outward), vertex(p3, outward));
  }

  void box(const glm::vec3& lo, const glm::vec3& hi) {
    ++s_.mesh_count;
    for (int axis = 0; axis < 3; ++axis) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int side = 0; side < 2; ++side) {
        glm::vec3 n(0.0f), c[4];
        n[axis] = side ? 1.0f : -1.0f;
        const float at = side ? hi[axis] : lo[axis];
        const float us[4] = {lo[u], hi[u], hi[u], lo[u]}, vs[4] = {lo[v], lo[v], hi[v], hi[v]};
        for (int k = 0; k < 4; ++k) c[k][axis] = at, c[k][u] = us[k], c[k][v] = vs[k];
        flat_quad(c[0], c[1], c[2], c[3], n);
      }
    }
  }

  // Upright cylinder standing on `base` (its bottom centre); smooth sides, flat caps.
  void cylinder(const glm::vec3& base, float r, float h, int sides, bool caps = true) {
    ++s_.mesh_count;
    wall(base, r, h, sides, 1.0f);
    if (caps) disk(base + glm::vec3(0, h, 0), r, sides, 1.0f), disk(base, r, sides, -1.0f);
  }

  // A round basin rim: outer wall facing out, inner wall facing the axis, flat top ring; open bottom (it
  // stands on the floor).
  void ring(const glm::vec3& base, float r_in, float r_out, float h, int sides) {
    ++s_.mesh_count;
    wall(base, r_out, h, sides, 1.0f);
    wall(base, r_in, h, sides, -1.0f);
    const glm::vec3 up(0, 1, 0), top = base + glm::vec3(0, h, 0);
    for (int i = 0; i < sides; ++i) {
      glm::vec3 d0 = dir(i, sides), d1 = dir(i + 1, sides);
      flat_quad(top + r_in * d0, top + r_out * d0, top + r_out * d1, top + r_in * d1, up);
    }
  }

  // UV sphere with its poles on the Y axis, so the bottom pole is exactly centre - (0, r, 0): a sphere of
  // centre height r touches the ground plane at one vertex.
  void sphere(const glm::vec3& c, float r, int slices, int stacks) {
    ++s_.mesh_count;
    const std::uint32_t top = vertex(c + glm::vec3(0, r, 0), {0, 1, 0});
    std::vector<std::uint32_t> prev;
    for (int j = 1; j < stacks; ++j) {
      float phi = kPi * static_cast<float>(j) / static_cast<float>(stacks);
      std::vector<std::uint32_t> ring;
      for (int i = 0; i < slices; ++i) {
        glm::vec3 n = std::sin(phi) * dir(i, slices) + glm::vec3(0, std::cos(phi), 0);
        ring.push_back(vertex(c + r * n, n));
      }
      for (int i = 0; i < slices; ++i) {
        int k = (i + 1) % slices;
        if (prev.empty())
          tri(top, ring[i], ring[k]);
        else
          quad(prev[i], ring[i], ring[k], prev[k]);
      }
      prev = std::move(ring);
    }
    const std::uint32_t bottom = vertex(glm::vec3(c.x, c.y - r, c.z), {0, -1, 0});
    for (int i = 0; i < slices; ++i) tri(bottom, prev[(i + 1) % slices], prev[i]);
  }

  // One bay of an arcade along X: the wall between two column centres x0, x1 from the springing height y0
  // to y1, depth z0..z1, pierced by a semicircular arch of radius (x1 - x0) / 2 - c (c: half the capital
  // width) made of `segments` straight pieces. Front and back faces are vertical strips above each arch
  // segment; the soffit (the arch's underside) has smooth normals pointing to the arch centre. The bay ends
  // are left open: they are shared with the neighbouring bay or the end wall.
  void arch_bay(float x0, float x1, float c, float y0, float y1, float z0, float z1, int segments) {
    ++s_.mesh_count;
    const float xm = 0.5f * (x0 + x1), r = 0.5f * (x1 - x0) - c;
    const glm::vec3 front(0, 0, 1), back(0, 0, -1);
    auto faces = [&](float xa, float ya, float xb, float yb) {  // strip from (xa, ya)-(xb, yb) up to y1
      flat_quad({xa, ya, z1}, {xb, yb, z1}, {xb, y1, z1}, {xa, y1, z1}, front);
      flat_quad({xa, ya, z0}, {xb, yb, z0}, {xb, y1, z0}, {xa, y1, z0}, back);
    };
    faces(x0, y0, xm - r, y0);  // above the capitals
    faces(xm + r, y0, x1, y0);
    std::uint32_t pf = 0, pb = 0;
    glm::vec2 prev;
    for (int i = 0; i <= segments; ++i) {
      float a = kPi * (1.0f - static_cast<float>(i) / static_cast<float>(segments));  // left to right
      glm::vec2 p(xm + r * std::cos(a), y0 + r * std::sin(a));
      glm::vec3 n(-std::cos(a), -std::sin(a), 0.0f);  // towards the arch centre
      std::uint32_t f = vertex({p.x, p.y, z1}, n), b = vertex({p.x, p.y, z0}, n);
      if (i > 0) {
        faces(prev.x, prev.y, p.x, p.y);
        quad(pf, f, b, pb);
      }
      pf = f, pb = b, prev = p;
    }
    flat_quad({x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}, {0, 1, 0});
  }

 private:
  static glm::vec3 dir(int i, int n) {
    float a = 2.0f * kPi * static_cast<float>(i % n) / static_cast<float>(n);
    return {std::cos(a), 0.0f, std::sin(a)};
  }
  // Cylindrical wall; `facing` +1 outwards, -1 towards the axis.
  void wall(const glm::vec3& base, float r, float h, int sides, float facing) {
    std::vector<std::uint32_t> lo, hi;
    for (int i = 0; i < sides; ++i) {
      glm::vec3 d = dir(i, sides);
      lo.push_back(vertex(base + r * d, facing * d));
      hi.push_back(vertex(base + r * d + glm::vec3(0, h, 0), facing * d));
    }
    for (int i = 0; i < sides; ++i) quad(lo[i], lo[(i + 1) % sides], hi[(i + 1) % sides], hi[i]);
  }
  void disk(const glm::vec3& c, float r, int sides, float facing) {
    const glm::vec3 n(0, facing, 0);
    std::uint32_t centre = vertex(c, n), first = vertex(c + r * dir(0, sides), n), prev = first;
    for (int i = 1; i <= sides; ++i) {
      std::uint32_t v = i == sides ? first : vertex(c + r * dir(i, sides), n);
      tri(centre, prev, v);
      prev = v;
    }
  }

  Scene& s_;
  glm::mat4 m_{1.0f};
  glm::mat3 n_{1.0f};
};

// `dolly`: how far the camera path moves sideways (to the view's right), as a share of the view distance.
View view(std::string name, glm::vec3 eye, glm::vec3 target, float near, float dolly = 0.0f, float fov = 60.0f) {
  View v;
  v.name = std::move(name);
  v.eye = eye, v.target = target, v.near_plane = near, v.fov_y_deg = fov;
  v.path_offset = dolly * glm::length(target - eye) * glm::normalize(glm::cross(target - eye, v.up));
  return v;
}

glm::mat4 placed(const glm::vec3& at, float yaw_deg) {
  return glm::rotate(glm::translate(glm::mat4(1.0f), at), glm::radians(yaw_deg), glm::vec3(0, 1, 0));
}

// Sponza-like courtyard, 32 x 16 m inside, walls 13 m high and no roof over the court. Along both long
// sides: a ground arcade (10 bays of 3.2 m on round columns, arches springing at 3.8 m), a gallery floor,
// an upper arcade with a balustrade, and a roof over the gallery. In the court: steps at the west end, a
// round basin with a sphere on a pedestal, urns on pedestals, a few crates. Occluders from 11 cm balusters
// to 13 m walls.
void atrium(Scene& s) {
  Builder b(s);
  const float X = 16.0f, Z = 8.0f, H = 13.0f, T = 0.6f;  // inner half-extents, wall height and thickness
  b.box({-X - T, -0.3f, -Z - T}, {X + T, 0.0f, Z + T});  // floor slab
  b.box({-X - T, 0.0f, Z}, {X + T, H, Z + T});
  b.box({-X - T, 0.0f, -Z - T}, {X + T, H, -Z});
  b.box({X, 0.0f, -Z}, {X + T, H, Z});
  b.box({-X - T, 0.0f, -Z}, {-X, H, Z});

  const float bay = 3.2f;
  const int bays = 10;  // 2 * X / bay
  for (float side : {-1.0f, 1.0f}) {
    b.transform(glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, side)));  // mirror the +z arcade to -z
    const float zc = 4.5f;
    // Ground arcade: plinth, shaft, capital; bays spring from the capitals (half-width 0.4) at 3.8 m.
    for (int k = 1; k < bays; ++k) {
      float x = -X + bay * static_cast<float>(k);
      b.box({x - 0.45f, 0.0f, zc - 0.45f}, {x + 0.45f, 0.18f, zc + 0.45f});
      b.box({x - 0.38f, 0.18f, zc - 0.38f}, {x + 0.38f, 0.3f, zc + 0.38f});
      b.cylinder({x, 0.3f, zc}, 0.3f, 3.2f, 32);
      b.box({x - 0.34f, 3.5f, zc - 0.34f}, {x + 0.34f, 3.62f, zc + 0.34f});
      b.box({x - 0.4f, 3.62f, zc - 0.4f}, {x + 0.4f, 3.8f, zc + 0.4f});
    }
    for (float e : {-1.0f, 1.0f})  // piers against the end walls carry the outermost arches
      b.box({e > 0 ? X - 0.4f : -X, 0.0f, zc - 0.4f}, {e > 0 ? X : -X + 0.4f, 3.8f, zc + 0.4f});
    for (int k = 0; k < bays; ++k) {
      float x0 = -X + bay * static_cast<float>(k);
      b.arch_bay(x0, x0 + bay, 0.4f, 3.8f, 5.5f, zc - 0.4f, zc + 0.4f, 32);
    }
    b.box({-X, 5.5f, zc - 0.4f}, {X, 5.75f, Z});  // gallery floor

    // Upper arcade on the gallery edge, with a balustrade between its columns.
    for (int k = 1; k < bays; ++k) {
      float x = -X + bay * static_cast<float>(k);
      b.box({x - 0.3f, 5.75f, zc - 0.3f}, {x + 0.3f, 5.95f, zc + 0.3f});
      b.cylinder({x, 5.95f, zc}, 0.22f, 2.5f, 32);
      b.box({x - 0.3f, 8.45f, zc - 0.3f}, {x + 0.3f, 8.65f, zc + 0.3f});
    }
    for (float e : {-1.0f, 1.0f})
      b.box({e > 0 ? X - 0.3f : -X, 5.75f, zc - 0.3f}, {e > 0 ? X : -X + 0.3f, 8.65f, zc + 0.3f});
    for (int k = 0; k < bays; ++k) {
      float x0 = -X + bay * static_cast<float>(k);
      b.arch_bay(x0, x0 + bay, 0.3f, 8.65f, 10.3f, zc - 0.3f, zc + 0.3f, 32);
      float a = x0 + 0.3f, c = x0 + bay - 0.3f;  // between the column plinths (and the end piers)
      b.box({a, 5.75f, zc - 0.12f}, {c, 5.87f, zc + 0.12f});
      b.box({a, 6.6f, zc - 0.12f}, {c, 6.75f, zc + 0.12f});
      const int balusters = 8;
      for (int i = 0; i < balusters; ++i)
        b.cylinder({a + (c - a) * (static_cast<float>(i) + 0.5f) / balusters, 5.87f, zc}, 0.055f, 0.73f, 12);
    }
    b.box({-X, 10.3f, zc - 0.3f}, {X, 10.55f, Z});  // gallery roof
  }
  b.identity();

  for (int i = 0; i < 3; ++i)  // steps up to the west wall
    b.box({-X, 0.15f * static_cast<float>(i), -3.0f},
          {-X + 2.4f - 0.4f * static_cast<float>(i), 0.15f * static_cast<float>(i + 1), 3.0f});
  b.ring({0, 0, 0}, 1.5f, 1.8f, 0.55f, 48);  // basin
  b.cylinder({0, 0, 0}, 0.2f, 0.9f, 16);
  b.sphere({0, 0.9f + 0.35f, 0}, 0.35f, 32, 16);
  for (float x : {-9.6f, 9.6f})
    for (float z : {-2.5f, 2.5f}) {
      b.box({x - 0.35f, 0.0f, z - 0.35f}, {x + 0.35f, 1.0f, z + 0.35f});
      b.sphere({x, 1.0f + 0.3f, z}, 0.3f, 32, 16);
    }
  b.transform(placed({11.0f, 0.0f, -1.5f}, 15.0f));  // crates
  b.box({-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
  b.transform(placed({11.1f, 1.0f, -1.45f}, -20.0f));
  b.box({-0.3f, 0.0f, -0.3f}, {0.3f, 0.6f, 0.3f});
  b.transform(placed({12.3f, 0.0f, 0.8f}, 40.0f));
  b.box({-0.7f, 0.0f, -0.45f}, {0.7f, 0.8f, 0.45f});
  b.identity();

  s.ao_radius = 0.5f;
  s.views = {
      // From the east end at gallery height, down the court towards the steps at the west end.
      view("overview", {15.0f, 7.0f, 0.0f}, {-8.0f, 2.2f, 0.0f}, 0.1f, 0.02f),
      // Base of the middle column of the south arcade, 1.8 m away: a 0.5 m kernel spans half the frame.
      view("closeup", {1.0f, 0.7f, -2.9f}, {0.0f, 0.3f, -4.3f}, 0.05f, 0.03f),
      // From the court up past the north arcade into the open sky.
      view("background", {-6.0f, 1.6f, -2.0f}, {-3.0f, 9.0f, 2.5f}, 0.1f),
  };
}

// Spheres of 0.25 to 1.5 m resting on a 40 x 40 m ground slab (none touch each other).
void spheres(Scene& s) {
  Builder b(s);
  b.box({-20.0f, -0.3f, -20.0f}, {20.0f, 0.0f, 20.0f});
  struct Ball {
    float x, z, r;
  };
  for (Ball ball : {Ball{0.0f, 0.0f, 1.5f}, Ball{2.6f, 0.8f, 0.6f}, Ball{-2.4f, 0.9f, 0.9f}, Ball{1.0f, 2.6f, 0.35f},
                    Ball{3.6f, -1.6f, 1.0f}, Ball{-4.2f, 1.8f, 0.25f}, Ball{-1.2f, 3.0f, 0.5f}}) {
    int slices = ball.r >= 0.5f ? 48 : 32;
    b.sphere({ball.x, ball.r, ball.z}, ball.r, slices, slices / 2);
  }
  s.ao_radius = 0.3f;
  s.views = {
      view("overview", {1.5f, 6.0f, 9.5f}, {0.0f, 0.5f, 0.0f}, 0.1f, 0.02f),
      // Into the crease under the big sphere, where it meets the ground.
      view("closeup", {-0.5f, 0.45f, 2.5f}, {0.05f, 0.12f, 0.95f}, 0.05f, 0.03f),
      // Low, looking out over the spheres to the edge of the ground and the empty sky above it.
      view("background", {0.0f, 1.2f, 8.0f}, {0.0f, -1.33f, -10.0f}, 0.1f),
  };
}

// A flight of 8 steps (0.18 m rise, 0.3 m run) up to a back wall, a side wall making an inner corner with
// the floor and the back wall, and open floor in front.
void stairs(Scene& s) {
  Builder b(s);
  b.box({-8.0f, -0.3f, -0.4f}, {8.0f, 0.0f, 12.0f});  // floor
  b.box({-4.4f, 0.0f, -0.4f}, {8.0f, 4.0f, 0.0f});    // back wall
  b.box({-4.4f, 0.0f, 0.0f}, {-4.0f, 4.0f, 5.0f});    // side wall
  for (int i = 0; i < 8; ++i)
    b.box({-1.0f, 0.18f * static_cast<float>(i), 0.0f},
          {1.5f, 0.18f * static_cast<float>(i + 1), 2.4f - 0.3f * static_cast<float>(i)});
  s.ao_radius = 0.25f;
  s.views = {
      view("overview", {4.5f, 2.8f, 6.5f}, {-1.0f, 0.8f, 0.8f}, 0.1f, 0.02f),
      // Where the lowest steps meet the floor and the flight's side.
      view("closeup", {2.6f, 0.8f, 3.6f}, {0.9f, 0.15f, 2.3f}, 0.05f, 0.03f),
      // From the wall out over the open floor to its edge and the sky.
      view("background", {3.5f, 1.8f, 0.4f}, {-1.5f, 0.3f, 7.0f}, 0.1f),
  };
}

// The Cornell box (measured data, 1 unit = 100 mm of the original, so 5.5 m): floor, ceiling, back and
// side walls, open front towards +z, a short and a tall block rotated about 17 degrees opposite ways.
void cornell(Scene& s) {
  Builder b(s);
  const float X = 2.78f, H = 5.488f, D = 5.592f, T = 0.1f;
  b.box({-X - T, -T, -D - T}, {X + T, 0.0f, 0.0f});      // floor
  b.box({-X - T, H, -D - T}, {X + T, H + T, 0.0f});      // ceiling
  b.box({-X - T, 0.0f, -D - T}, {X + T, H, -D});         // back wall
  b.box({-X - T, 0.0f, -D}, {-X, H, 0.0f});              // left wall
  b.box({X, 0.0f, -D}, {X + T, H, 0.0f});                // right wall
  b.transform(placed({0.925f, 0.0f, -1.685f}, -17.0f));  // short block
  b.box({-0.835f, 0.0f, -0.835f}, {0.835f, 1.65f, 0.835f});
  b.transform(placed({-0.905f, 0.0f, -3.51f}, 17.2f));  // tall block
  b.box({-0.83f, 0.0f, -0.835f}, {0.83f, 3.3f, 0.835f});
  b.identity();
  s.ao_radius = 0.3f;
  s.views = {
      view("overview", {0.0f, 2.744f, 8.5f}, {0.0f, 2.744f, -2.8f}, 0.1f, 0.02f, 40.0f),
      // The short block's front foot, 1.7 m away.
      view("closeup", {-0.4f, 0.8f, 0.6f}, {0.7f, 0.15f, -0.9f}, 0.05f, 0.03f),
      // From outside, up and to the right: the box fills the lower left, sky the rest.
      view("background", {-1.6f, 3.8f, -5.2f}, {1.2f, 2.3f, 3.0f}, 0.1f),
  };
}

// Stress scene (issue 7): a floor and three boxes, plus geometry a real asset pipeline lets through and a
// renderer must survive: zero-area triangles (one vertex index three times, three vertices at one point,
// three collinear vertices), needle slivers 0.1 mm wide (standing, lying on the floor, and a fan seen
// nearly end-on), vertices with zero-length normals (a whole panel, and one corner of an otherwise lit face), and
// a two-sided card whose front and back faces share their vertices, so that each vertex's smooth normal,
// the sum of its faces' normals, is zero. load_scene keeps these normals as they are (kBuiltins below), so
// the G-buffer's ao_safe_normalize and every method see them; the reference tracer uses Embree's geometric
// normals and never hits a zero-area triangle.
void degenerate(Scene& s) {
  Builder b(s);
  b.box({-8.0f, -0.3f, -8.0f}, {8.0f, 0.0f, 8.0f});  // floor
  b.box({-3.0f, 0.0f, -3.0f}, {-1.0f, 1.5f, -1.0f});
  b.box({1.0f, 0.0f, -2.5f}, {2.5f, 0.8f, -1.0f});
  b.box({-0.5f, 0.0f, -4.0f}, {0.5f, 2.0f, -3.0f});
  const glm::vec3 up(0, 1, 0), zero(0.0f);

  // Zero-area triangles, on the floor and in the air (they rasterise to nothing; a shader that divides by
  // their area or normalises their cross product gets 0 / 0).
  b.mesh();
  for (glm::vec3 p : {glm::vec3(0.5f, 0.0f, 0.5f), glm::vec3(-1.5f, 0.7f, 0.8f)}) {
    std::uint32_t v = b.raw_vertex(p, up);
    b.raw_tri(v, v, v);                                                              // one index three times
    b.raw_tri(b.raw_vertex(p, up), b.raw_vertex(p, zero), b.raw_vertex(p, -up));  // three vertices, one point
  }
  // Collinear: along x on the floor, and along a diagonal with exact binary steps (the cross product is 0).
  b.raw_tri(b.raw_vertex({-2.0f, 0.0f, 1.0f}, up), b.raw_vertex({-1.0f, 0.0f, 1.0f}, up),
            b.raw_vertex({0.5f, 0.0f, 1.0f}, up));
  const glm::vec3 a(1.0f, 0.25f, 1.0f), d(0.25f, 0.5f, -0.125f);
  b.raw_tri(b.raw_vertex(a, up), b.raw_vertex(a + d, up), b.raw_vertex(a + 2.5f * d, zero));

  // Needle slivers 1e-4 m wide: three standing 2.5 m tall, two lying 1 mm over the floor, and a fan of
  // eight radiating from one point towards and across the cameras (seen nearly end-on).
  b.mesh();
  auto sliver = [&](glm::vec3 p, glm::vec3 q, glm::vec3 side) {
    glm::vec3 n = glm::cross(side, q - p);
    b.tri(b.vertex(p, n), b.vertex(p + 1e-4f * side, n), b.vertex(q, n));
  };
  for (float x : {-0.6f, 0.0f, 0.6f}) sliver({x, 0.0f, 2.0f}, {x, 2.5f, 2.0f}, {1, 0, 0});
  sliver({-3.0f, 0.001f, 3.0f}, {3.0f, 0.001f, 3.2f}, {0, 0, 1});
  sliver({2.0f, 0.001f, 0.0f}, {2.6f, 0.001f, 4.0f}, {-1, 0, 0});
  for (int i = 0; i < 8; ++i) {
    float t = 2.0f * kPi * static_cast<float>(i) / 8.0f;
    glm::vec3 dir(std::cos(t), 0.5f + 0.4f * std::sin(t), std::sin(t) + 1.2f);
    sliver({-2.0f, 1.0f, -0.5f}, glm::vec3(-2.0f, 1.0f, -0.5f) + 1.5f * glm::normalize(dir), {0, 1, 0});
  }

  // Zero-length normals: a standing 1 x 1.5 m panel with zero normals at all four corners (the interpolated
  // normal is exactly zero everywhere on it), and a 1 m cube whose top face has one zero-normal corner.
  b.mesh();
  {
    std::uint32_t p0 = b.raw_vertex({1.0f, 0.0f, 0.5f}, zero), p1 = b.raw_vertex({2.0f, 0.0f, 0.5f}, zero),
                  p2 = b.raw_vertex({2.0f, 1.5f, 0.5f}, zero), p3 = b.raw_vertex({1.0f, 1.5f, 0.5f}, zero);
    b.raw_tri(p0, p1, p2), b.raw_tri(p0, p2, p3);  // counter-clockwise seen from +z
  }
  b.box({3.0f, 0.0f, -0.5f}, {4.0f, 1.0f, 0.5f});
  {
    std::uint32_t t0 = b.raw_vertex({3.0f, 1.001f, 0.5f}, zero), t1 = b.raw_vertex({4.0f, 1.001f, 0.5f}, up),
                  t2 = b.raw_vertex({4.0f, 1.001f, -0.5f}, up), t3 = b.raw_vertex({3.0f, 1.001f, -0.5f}, up);
    b.raw_tri(t0, t1, t2), b.raw_tri(t0, t2, t3);  // a lid 1 mm over the top, counter-clockwise from above
  }

  // Two-sided card (a leaf, a sign): front and back faces share the four vertices, so each vertex's smooth
  // normal, front + back, is exactly zero.
  b.mesh();
  {
    const glm::vec3 front(0, 0, 1), smooth = front + -front;
    std::uint32_t c0 = b.raw_vertex({-1.0f, 0.0f, 0.0f}, smooth), c1 = b.raw_vertex({0.0f, 0.0f, 0.0f}, smooth),
                  c2 = b.raw_vertex({0.0f, 1.2f, 0.0f}, smooth), c3 = b.raw_vertex({-1.0f, 1.2f, 0.0f}, smooth);
    b.raw_tri(c0, c1, c2), b.raw_tri(c0, c2, c3);  // front, counter-clockwise from +z
    b.raw_tri(c0, c2, c1), b.raw_tri(c0, c3, c2);  // back, counter-clockwise from -z
  }
  b.identity();

  s.ao_radius = 0.3f;
  s.views = {
      // From front-right above: the floor, the boxes, the card, the panel and the needles.
      view("overview", {5.0f, 4.0f, 8.0f}, {0.5f, 0.0f, -0.5f}, 0.1f, 0.02f),
      // Down at 45 degrees onto the zero-normal panel, with the card and the standing needles, 3.7 m away.
      view("closeup", {0.5f, 3.2f, 3.0f}, {1.5f, 0.5f, 0.6f}, 0.05f, 0.03f),
      // Low over the floor, out past its far edge into the sky.
      view("background", {0.0f, 1.2f, 6.5f}, {0.0f, -0.9f, -10.0f}, 0.1f),
  };
}

// Stress scene (issue 7): a city seen from far away. A 3000 x 3600 unit ground slab carries a grid of
// 60 x 60 blocks 40-290 high (the taller ones with a setback on top) along 40-unit streets, 450-3500 units
// from the cameras, which stay 200-600 units up outside the grid, so that every visible surface lies
// 200-4000 units deep (view-space depth). The 8-unit AO radius suits the city's details (a setback is
// 1.5 radii, a street 5), not the distance: r16f linear depth steps by 0.25-2 units there (0.25 at 256-512,
// 2 at 2048-4096), so a radius spans only 4-30 r16f steps where the atrium's 0.5 m spans 30-200. Float
// spacing is relative, and so are the templates' depth biases, so what bands is a small radius for its
// depth (radius / depth 0.002-0.02 here, 0.0125-0.1 in the atrium), not the distance itself: r16f bands
// here where r32f (steps under 0.5 mm) does not (tests/stress/test_stress_geometry.cpp measures it).
void far_city(Scene& s) {
  Builder b(s);
  b.box({-1500.0f, -20.0f, -3600.0f}, {1500.0f, 0.0f, 0.0f});  // ground
  for (int i = 0; i < 28; ++i)
    for (int j = 0; j < 31; ++j) {
      const float x = -1370.0f + 100.0f * static_cast<float>(i), z = -480.0f - 100.0f * static_cast<float>(j);
      const float h = 40.0f + 25.0f * static_cast<float>((7 * i + 13 * j) % 11);
      b.box({x - 30.0f, 0.0f, z - 30.0f}, {x + 30.0f, h, z + 30.0f});
      if (h > 150.0f) b.box({x - 18.0f, h, z - 18.0f}, {x + 18.0f, h + 40.0f, z + 18.0f});
    }

  s.ao_radius = 8.0f;
  s.views = {
      // From 600 up, 300 beyond the slab's near edge, down over the city (16 degrees below level).
      view("overview", {0.0f, 600.0f, 300.0f}, {0.0f, 0.0f, -1800.0f}, 1.0f, 0.02f),
      // Down at 35 degrees onto the first street crossing, 390 units away (the frame's bottom edge is 214
      // deep).
      view("closeup", {-20.0f, 224.0f, -120.0f}, {-20.0f, 0.0f, -440.0f}, 1.0f, 0.03f),
      // Level, 200 up, over the city into the sky.
      view("background", {0.0f, 200.0f, 350.0f}, {0.0f, 200.0f, -1000.0f}, 1.0f),
  };
}

struct Builtin {
  const char* name;
  void (*make)(Scene&);
  bool raw_normals = false;  // load_scene keeps the normals as built (zero-length ones included)
};
constexpr Builtin kBuiltins[] = {{"atrium", atrium},   {"spheres", spheres},
                                 {"stairs", stairs},   {"cornell", cornell},
                                 {"degenerate", degenerate, true}, {"far", far_city}};

}  // namespace

bool builtin_keeps_normals(std::string_view name) {
  for (const Builtin& b : kBuiltins)
    if (name == b.name) return b.raw_normals;
  return false;
}

std::vector<std::string> builtin_names() {
  std::vector<std::string> out;
  for (const Builtin& b : kBuiltins) out.emplace_back(b.name);
  return out;
}

Scene make_builtin(std::string_view name) {
  for (const Builtin& b : kBuiltins) {
    if (name != b.name) continue;
    Scene s;
    b.make(s);
    Bounds bounds;
    for (const glm::vec3& p : s.positions) bounds.extend(p);
    for (View& v : s.views) fit_planes(v, bounds, v.near_plane);
    return s;
  }
  std::string names;
  for (const Builtin& b : kBuiltins) names += fmt::format("{}builtin:{}", names.empty() ? "" : ", ", b.name);
  fail(fmt::format("builtin:{}: error: unknown built-in scene (available: {})", name, names));
}

}  // namespace aovar::scene::detail
