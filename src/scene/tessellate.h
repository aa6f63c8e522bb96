#pragma once
// "SPEC@tessellate=N": every triangle split into 4^N by its edge midpoints, the same surface with more
// triangles. What a renderer pays for geometry grows with the triangle count while the AO passes do not, and
// no scene of a million triangles ships with the tests: Sponza@tessellate=2 has 1.06 million (issue 55's
// scaling bench, bench/scene_scale).
#include "scene/scene.h"

namespace aovar::scene {

inline constexpr int kMaxTessellateLevels = 4;                    // 256 triangles for one
inline constexpr std::size_t kMaxTessellatedTriangles = 1u << 26;  // 67 million: about 2.4 GB of vertices

// Splits every triangle of `scene` into four, `levels` times. A midpoint is computed from its edge's two ends
// alone ((a + b) / 2, the same floats from either triangle of the edge), so the mesh stays watertight where
// it was; its normal is the normalised sum of the ends' normals. Throws SceneError (naming `display`)
// when the result would exceed kMaxTessellatedTriangles or the 32-bit index range.
void tessellate(Scene& scene, int levels, const std::string& display);

}  // namespace aovar::scene
