#pragma once
// Shared helpers of the rendering tests: compiled variants, hand-built scenes, one-call rendering.
#include <map>
#include <mutex>
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
// The same for `targets` only (a test of one target's plans or embedding); throws when a program fails.
compile::CompiledSpace compile_variants(const std::vector<std::string>& keys, std::vector<variants::Target> targets);

// Tiny and fast measure options: builtin:stairs at 64x36, one timed round, no warm-up, compile and
// reference caches in `dir`, output in dir/m; `globs` selected, `baseline` timed in every round.
measure::MeasureOptions tiny_measure(const std::filesystem::path& dir, std::vector<std::string> globs,
                                     const std::string& baseline);
int variant_index(const compile::CompiledSpace& c, const std::string& key);  // throws when absent

variants::Target target_of(const std::string& backend);

// Variants compiled once, on first use, for the tests of one file (a file-scope object with a name of its
// own: unity batches put several test files in one translation unit).
class CompiledVariants {
 public:
  explicit CompiledVariants(std::vector<std::string> keys, bool with_gles = false)
      : keys_(std::move(keys)), with_gles_(with_gles) {}
  const compile::CompiledSpace& space() const;
  // The plan of variant `key` (throws when it was not compiled) for `backend`'s target.
  render::PipelinePlan plan(const std::string& key, const std::string& backend) const;

 private:
  std::vector<std::string> keys_;
  bool with_gles_;
  mutable std::once_flag once_;
  mutable compile::CompiledSpace space_;
};

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

// A w x h image of one value.
inline image::FloatImage filled_image(int w, int h, float v) {
  return {w, h, std::vector<float>(static_cast<std::size_t>(w) * h, v)};
}

// Axis-aligned quads merged into a scene with one view; each quad is (corner, edge u, edge v), normal u x v.
struct Quad {
  glm::vec3 corner, u, v;
};
scene::Scene quad_scene(const std::vector<Quad>& quads, const scene::View& view, float radius);

// A 40 x 40 floor seen from above at an angle, and a wall standing on it across the view (z = -2).
scene::View floor_view();
inline const Quad kFloor{{-20.0f, 0.0f, 20.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -40.0f}};
inline const Quad kWall{{-20.0f, 0.0f, -2.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 20.0f, 0.0f}};

// A 2 x 2 x 2 box standing on the centre of a square floor `floor_size` wide (y = 0), seen from `view`.
scene::Scene box_scene(const scene::View& view, float radius, float floor_size = 20.0f);
Quad square_floor(float size);  // centred on the origin at y = 0, facing up

// The variants the backend tests render (the first is the plain baseline): separable / bilateral blur, half
// and quarter resolution, r16f depth, mediump, every normal encoding, the position buffer, progressive, SAO's
// z MIP pyramid (per-level views) and unsharp's depth prefilter (binding 7).
const std::vector<std::string>& backend_test_keys();

// The backend tests' box: box_scene() on a 20 x 20 floor at AO radius kBoxRadius, seen by box_view() from the
// front, slightly from the right and above; box_frame() is a still frame of it.
inline constexpr float kBoxRadius = 0.5f;
scene::View box_view(float far_plane = 50.0f);
scene::Scene box_on_floor();  // box_scene(box_view(), kBoxRadius)
render::FrameSetup box_frame(const scene::View& view, int frame);
// The image has `size` and only finite pixels in [0, 1].
void expect_sane(const image::FloatImage& img, render::Extent size, const std::string& what);
// Open floor far from the box stays open; the floor at the foot of the box's front face is darker.
void expect_box_occlusion(const image::FloatImage& img, render::Extent size, const std::string& what);

// Renders `frames` frames of a plan (static camera) and reads the result back.
image::FloatImage render_plan(render::Backend& backend, const render::PipelinePlan& plan, const scene::View& view,
                              render::Extent size, float radius, int frames, int first_frame = 0);

// Pixel (x, y; row 0 = bottom) where a world point lands in `view` at `size`.
glm::ivec2 project(const scene::View& view, render::Extent size, glm::vec3 world);

// A floor meeting a wall (quad_scene {kFloor, kWall} seen from floor_view) at `size`: the pixels of a point in
// their inner corner and of a point of open floor next to it (four radii out), both on screen. Every AO method
// shades the corner darker than the open floor.
struct CornerProbe {
  scene::View view;
  scene::Scene scene;
  render::Extent size;
  float radius = 0;
  glm::ivec2 corner{0, 0}, open{0, 0};
};
CornerProbe corner_probe(float radius = 0.5f, render::Extent size = {320, 180});

// A hand-written GLSL program of a plan (the GL backends' tests).
render::Shader glsl_shader(const std::string& key, variants::StageKind stage, const std::string& glsl);

// The GL backends' read-back tests: a fragment main() writing x + 1000 y to o_color.r (pixel coordinates),
// NaN at (0, 0), +Inf at (1, 0), -Inf at (2, 0); and the check of its image.
extern const char* const kReadbackPatternMain;
void expect_readback_pattern(const image::FloatImage& img, int width, int height);

struct ImageDiff {
  double mean_abs = 0, max_abs = 0;
};
ImageDiff compare(const image::FloatImage& a, const image::FloatImage& b);

}  // namespace aovar::test
