#pragma once
// Hemisphere sampling of the reference (internal to src/reference, tested directly): a 2D Sobol
// (0,2)-sequence, a per-pixel Cranley-Patterson rotation and Malley's method (uniform disc points lifted to
// the hemisphere give cosine-weighted directions).
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace aovar::reference::detail {

// Point i of the first two Sobol dimensions: dimension 0 is the base-2 van der Corput sequence (bit
// reversal), dimension 1 uses the generator of the primitive polynomial x + 1 (direction numbers
// v_{k+1} = v_k ^ (v_k >> 1)). Together they form a (0,2)-sequence: every power-of-two prefix is a
// (0,m,2)-net, i.e. stratified in every elementary interval of area 1/N.
inline glm::vec2 sobol2(std::uint32_t i) {
  std::uint32_t x = 0, y = 0, v = 1u << 31;
  for (std::uint32_t bit = 0; i != 0; i >>= 1, ++bit) {
    if (i & 1u) {
      x ^= 1u << (31 - bit);
      y ^= v;
    }
    v ^= v >> 1;
  }
  constexpr float kScale = 1.0f / 4294967296.0f;  // 2^-32
  // Keep 24 bits so that the float is exact and strictly below 1.
  return {static_cast<float>(x >> 8) * (kScale * 256.0f), static_cast<float>(y >> 8) * (kScale * 256.0f)};
}

// A 32-bit integer hash with good avalanche (the "lowbias32" mix of Chris Wellons' hash prospector).
inline std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// Cranley-Patterson shift of pixel (x, y): two uniform numbers in [0, 1) from a hash of the pixel, so that
// neighbouring pixels use unrelated rotations of the same point set (their errors do not correlate into
// visible patterns, and a box filter over pixels averages them down).
inline glm::vec2 pixel_shift(int x, int y) {
  std::uint32_t h0 = hash32(static_cast<std::uint32_t>(x) * 0x9e3779b9u ^ hash32(static_cast<std::uint32_t>(y) + 0x632be5abu));
  std::uint32_t h1 = hash32(h0 ^ 0x85ebca6bu);
  return {static_cast<float>(h0 >> 8) * (1.0f / 16777216.0f), static_cast<float>(h1 >> 8) * (1.0f / 16777216.0f)};
}

// u + shift modulo 1 (the toroidal rotation), staying in [0, 1).
inline glm::vec2 rotate(glm::vec2 u, glm::vec2 shift) {
  glm::vec2 r = u + shift;
  if (r.x >= 1.0f) r.x -= 1.0f;
  if (r.y >= 1.0f) r.y -= 1.0f;
  return r;
}

// Shirley and Chiu's concentric map from the unit square to the unit disc: area-preserving and with low
// distortion, so the square's stratification carries over to the disc.
inline glm::vec2 concentric_disc(glm::vec2 u) {
  float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  constexpr float kQuarterPi = 0.78539816339744831f;
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = kQuarterPi * (b / a);
  } else {
    r = b;
    phi = 2.0f * kQuarterPi - kQuarterPi * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// Malley's method: a uniform point on the disc projected up onto the hemisphere is cosine-distributed.
// Returns (x, y, z) in the local frame whose z axis is the normal.
inline glm::vec3 malley(glm::vec2 u) {
  glm::vec2 d = concentric_disc(u);
  float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

// Orthonormal tangent frame (t, b) of a unit normal n (Duff et al. 2017, branchless).
inline void tangent_frame(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
  float sign = std::copysign(1.0f, n.z);
  float a = -1.0f / (sign + n.z);
  float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

}  // namespace aovar::reference::detail
