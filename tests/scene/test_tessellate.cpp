// "SPEC@tessellate=N" (scene/tessellate.h): the same surface with 4^N times the triangles, for the geometry
// scaling bench; bad levels are one-line errors naming the spec.
#include <gtest/gtest.h>

#include <string>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/tessellate.h"
#include "test_support.h"

namespace aovar::test {
namespace {

double surface_area(const scene::Scene& s) {
  double area = 0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    const glm::vec3 a = s.positions[s.indices[3 * t]], b = s.positions[s.indices[3 * t + 1]],
                    c = s.positions[s.indices[3 * t + 2]];
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return area;
}

TEST(Tessellate, TheSameSurfaceWithFourTimesTheTrianglesPerLevel) {
  const scene::Scene plain = scene::load_scene("builtin:cornell");
  for (int levels : {1, 2}) {
    SCOPED_TRACE(levels);
    const scene::Scene fine = scene::load_scene("builtin:cornell@tessellate=" + std::to_string(levels));
    EXPECT_EQ(fine.triangle_count(), plain.triangle_count() << (2 * levels));
    EXPECT_EQ(fine.bounds.min, plain.bounds.min);
    EXPECT_EQ(fine.bounds.max, plain.bounds.max);
    EXPECT_NEAR(surface_area(fine), surface_area(plain), 1e-5 * surface_area(plain));
    for (const glm::vec3& n : fine.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    EXPECT_NE(fine.content_hash, plain.content_hash) << "another mesh in every cache";
    EXPECT_EQ(fine.views.size(), plain.views.size());
  }
  const scene::Scene both = scene::load_scene("builtin:cornell@scale=2@tessellate=1");
  const scene::Scene other_order = scene::load_scene("builtin:cornell@tessellate=1@scale=2");
  EXPECT_EQ(both.content_hash, other_order.content_hash);
  EXPECT_EQ(both.bounds.max, plain.bounds.max * 2.0f);
}

TEST(Tessellate, BadLevelsAreOneLineErrorsNamingTheSpec) {
  auto error = [](const std::string& spec) {
    return thrown_message<scene::SceneError>([&] { scene::load_scene(spec); });
  };
  EXPECT_TRUE(one_line_error_with(error("builtin:cornell@tessellate=0"), "must be a number from 1 to 4"));
  EXPECT_TRUE(one_line_error_with(error("builtin:cornell@tessellate=5"), "builtin:cornell@tessellate=5"));
  EXPECT_TRUE(one_line_error_with(error("builtin:cornell@tessellate=x"), "tessellate 'x'"));
  EXPECT_TRUE(one_line_error_with(error("builtin:cornell@tessellate=1.5"), "whole number"));
  EXPECT_TRUE(one_line_error_with(error("builtin:cornell@tessellate=1@tessellate=2"), "given twice"));
  EXPECT_TRUE(one_line_error_with(error("builtin:cornell@scale=0"), "must be a number from 1e-6 to 1e6"));

  scene::Scene huge;  // a million triangles (on three vertices) would become 256 million: refused before any work
  huge.positions.assign(3, glm::vec3(0.0f));
  huge.normals.assign(3, glm::vec3(0.0f, 1.0f, 0.0f));
  huge.indices.resize(3u << 20);
  for (std::size_t i = 0; i < huge.indices.size(); ++i) huge.indices[i] = static_cast<std::uint32_t>(i % 3);
  EXPECT_TRUE(one_line_error_with(thrown_message<scene::SceneError>([&] { scene::tessellate(huge, 4, "big.obj"); }),
                                  "big.obj: error: tessellating 4 times"));
  EXPECT_EQ(huge.indices.size(), 3u << 20) << "left as it was";
}

}  // namespace
}  // namespace aovar::test
