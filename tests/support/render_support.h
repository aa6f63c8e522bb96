#pragma once
// Shared helpers of the rendering tests: compiled variants, hand-built scenes, one-call rendering.
#include <map>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "image/image.h"
#include "measure/measure.h"
#include "render/backend.h"
#include "scene/scene.h"

namespace aovar::test {

// The default manifest compiled for vulkan and gl45 (and gles30 for the gles backend, `with_gles`: the ES
// programs add compile time most tests do not need), restricted to `keys` (exact keys or globs).
compile::CompiledSpace compile_variants(const std::vector<std::string>& keys, bool with_gles = false);

// Tiny and fast measure options: builtin:stairs at 64x36, one timed round, no warm-up, compile and
// reference caches in `dir`, output in dir/m; `globs` selected, `baseline` timed in every round.
measure::MeasureOptions tiny_measure(const std::filesystem::path& dir, std::vector<std::string> globs,
                                     const std::string& baseline);
int variant_index(const compile::CompiledSpace& c, const std::string& key);  // throws when absent

variants::Target target_of(const std::string& backend);

// Compiles the variants the kinds' globs select and picks, per kind (its index), the key of the first glob
// (in order of preference) that matches a variant; kinds that match nothing are absent from `keys`.
struct PickedVariants {
  compile::CompiledSpace compiled;
  std::map<int, std::string> keys;
};
PickedVariants pick_variants(const std::vector<std::vector<std::string>>& kinds, bool with_gles = false);

// The variant kinds a method's rendering tests use: a plain full-resolution 8-sample variant without blur
// (the estimator alone), a blurred 16-sample one, and a progressive half-resolution mediump one on r16f
// depth. Each kind lists globs in order of preference: methods that read no normals keep only
// `normals = depth` (a manifest rule), axes a method does not read show as `_x` in keys, and a method
// without a progressive form keeps p0.
std::vector<std::vector<std::string>> method_kinds(const std::string& algorithm);

// Axis-aligned quads merged into a scene with one view; each quad is (corner, edge u, edge v), normal u x v.
struct Quad {
  glm::vec3 corner, u, v;
};
scene::Scene quad_scene(const std::vector<Quad>& quads, const scene::View& view, float radius);

// A 40 x 40 floor seen from above at an angle, and a wall standing on it across the view (z = -2).
scene::View floor_view();
inline const Quad kFloor{{-20.0f, 0.0f, 20.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -40.0f}};
inline const Quad kWall{{-20.0f, 0.0f, -2.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 20.0f, 0.0f}};

// Renders `frames` frames of a plan (static camera) and reads the result back.
image::FloatImage render_plan(render::Backend& backend, const render::PipelinePlan& plan, const scene::View& view,
                              render::Extent size, float radius, int frames, int first_frame = 0);

// Pixel (x, y; row 0 = bottom) where a world point lands in `view` at `size`.
glm::ivec2 project(const scene::View& view, render::Extent size, glm::vec3 world);

// The GL backends' read-back tests: a fragment main() writing x + 1000 y to o_color.r (pixel coordinates),
// NaN at (0, 0), +Inf at (1, 0), -Inf at (2, 0); and the check of its image.
extern const char* const kReadbackPatternMain;
void expect_readback_pattern(const image::FloatImage& img, int width, int height);

struct ImageDiff {
  double mean_abs = 0, max_abs = 0;
};
ImageDiff compare(const image::FloatImage& a, const image::FloatImage& b);

}  // namespace aovar::test
