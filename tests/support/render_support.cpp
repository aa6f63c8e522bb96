#include "render_support.h"

#include <fnmatch.h>

#include <algorithm>

#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <stdexcept>

#include "test_support.h"

namespace aovar::test {

const char* const kReadbackPatternMain = R"(
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float v = float(p.x) + 1000.0 * float(p.y);
    if (p == ivec2(0, 0)) v = uintBitsToFloat(0x7fc00000u);       // NaN
    if (p == ivec2(1, 0)) v = uintBitsToFloat(0x7f800000u);       // +Inf
    if (p == ivec2(2, 0)) v = -uintBitsToFloat(0x7f800000u);      // -Inf
    o_color = vec4(v, 0.0, 0.0, 1.0);
}
)";

render::Shader glsl_shader(const std::string& key, variants::StageKind stage, const std::string& glsl) {
  render::Shader s;
  s.program_key = key;
  s.stage = stage;
  s.glsl = glsl;
  return s;
}

void expect_readback_pattern(const image::FloatImage& img, int width, int height) {
  ASSERT_EQ(img.width, width);
  ASSERT_EQ(img.height, height);
  EXPECT_TRUE(std::isnan(img.at(0, 0)));
  EXPECT_EQ(img.at(1, 0), std::numeric_limits<float>::infinity());
  EXPECT_EQ(img.at(2, 0), -std::numeric_limits<float>::infinity());
  for (int y = 0; y < height; ++y)
    for (int x = y == 0 ? 3 : 0; x < width; ++x) ASSERT_EQ(img.at(x, y), float(x + 1000 * y)) << x << "," << y;
}

measure::MeasureOptions tiny_measure(const std::filesystem::path& dir, std::vector<std::string> globs,
                                     const std::string& baseline) {
  measure::MeasureOptions o;
  o.scope.manifest = source_dir() / "shader_src" / "aovar.toml";
  o.scene = "builtin:stairs";
  o.globs = std::move(globs);
  o.baseline = baseline;
  o.size = {64, 36};
  o.timing.reps = 1;
  o.timing.warmup = 0;
  o.scope.cache_dir = dir / "cache";
  o.out = dir / "m";
  return o;
}

compile::CompiledSpace compile_variants(const std::vector<std::string>& keys, bool with_gles) {
  std::vector<variants::Target> targets = {variants::Target::vulkan, variants::Target::gl45};
  if (with_gles) targets.push_back(variants::Target::gles30);
  return compile_variants(keys, std::move(targets));
}

compile::CompiledSpace compile_variants(const std::vector<std::string>& keys, std::vector<variants::Target> targets) {
  compile::CompileOptions o;
  o.scope.targets = std::move(targets);
  o.globs = keys;
  auto c = compile::compile_space(aovar::test::on_manifest(o, source_dir() / "shader_src" / "aovar.toml"));
  if (!c.ok()) throw std::runtime_error("compile failed: " + (c.diagnostics.empty() ? "" : c.diagnostics[0]));
  return c;
}

int variant_index(const compile::CompiledSpace& c, const std::string& key) {
  for (std::size_t i = 0; i < c.space.variants.size(); ++i)
    if (c.space.variants[i].key == key) return static_cast<int>(i);
  throw std::runtime_error("no variant " + key);
}

variants::Target target_of(const std::string& backend) { return render::target_of(backend); }

const compile::CompiledSpace& CompiledVariants::space() const {
  std::call_once(once_, [this] { space_ = compile_variants(keys_, with_gles_); });
  return space_;
}

render::PipelinePlan CompiledVariants::plan(const std::string& key, const std::string& backend) const {
  return render::plan_pipeline(space(), variant_index(space(), key), target_of(backend));
}

scene::Scene quad_scene(const std::vector<Quad>& quads, const scene::View& view, float radius) {
  scene::Scene s;
  s.name = "test:quads";
  s.source = "test";
  for (const auto& q : quads) {
    auto base = static_cast<std::uint32_t>(s.positions.size());
    glm::vec3 n = glm::normalize(glm::cross(q.u, q.v));
    for (glm::vec3 p : {q.corner, q.corner + q.u, q.corner + q.u + q.v, q.corner + q.v}) {
      s.positions.push_back(p);
      s.normals.push_back(n);
      s.bounds.extend(p);
    }
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) s.indices.push_back(base + i);
    ++s.mesh_count;
  }
  s.content_hash = "test";
  s.ao_radius = radius;
  s.views = {view};
  return s;
}

Quad square_floor(float size) { return {{-size / 2, 0, size / 2}, {size, 0, 0}, {0, 0, -size}}; }

scene::Scene box_scene(const scene::View& view, float radius, float floor_size) {
  std::vector<Quad> quads = {
      {{-1, 0, 1}, {2, 0, 0}, {0, 2, 0}},   // front (+z)
      {{1, 0, -1}, {-2, 0, 0}, {0, 2, 0}},  // back
      {{1, 0, 1}, {0, 0, -2}, {0, 2, 0}},   // right (+x)
      {{-1, 0, -1}, {0, 0, 2}, {0, 2, 0}},  // left
      {{-1, 2, 1}, {2, 0, 0}, {0, 0, -2}},  // top
      square_floor(floor_size),
  };
  scene::Scene s = quad_scene(quads, view, radius);
  s.name = "test:box";
  return s;
}

const std::vector<std::string>& backend_test_keys() {
  static const std::vector<std::string> keys = {
      "alchemy-s08-p0-nrg8-zdep-rst-d32-bno-x1-hp",   "alchemy-s08-p0-nrgb8-zdep-rip-d32-bsep-x2-hp",
      "alchemy-s08-p0-nrgb8-zpos-rip-d16-bsep-x2-hp", "alchemy-s08-p0-noct-zdep-rst-d16-bbil-x4-mp",
      "alchemy-s08-p0-ndep-zpos-rip-d16-bsep-x1-hp",  "alchemy-s08-p1-nrg8-zdep-rst-d32-bsep-x1-hp",
      "alchemy-s08-p1-ndep-zdep-rip-d16-bsep-x4-mp",  "sao-s08-p1-ndep-zdep-rst-d32-bsep-x2-hp",
      "unsharp-s08-p0-ndep-zdep-_r-d16-bbil-x1-hp",
  };
  return keys;
}

scene::View box_view(float far_plane) {
  scene::View v;
  v.name = "box";
  v.eye = {2.0f, 2.5f, 6.0f};
  v.target = {0.0f, 0.5f, 0.0f};
  v.near_plane = 0.1f;
  v.far_plane = far_plane;
  return v;
}

scene::Scene box_on_floor() { return box_scene(box_view(), kBoxRadius); }

render::FrameSetup box_frame(const scene::View& view, int frame) {
  render::FrameSetup s;
  s.view = &view;
  s.frame = frame;
  s.static_camera = true;
  s.radius = kBoxRadius;
  return s;
}

void expect_sane(const image::FloatImage& img, render::Extent size, const std::string& what) {
  ASSERT_EQ(img.width, size.width) << what;
  ASSERT_EQ(img.height, size.height) << what;
  ASSERT_EQ(img.pixels.size(), std::size_t(size.width) * size.height) << what;
  int bad = 0;
  for (float v : img.pixels) bad += !(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
  EXPECT_EQ(bad, 0) << what << ": non-finite or out-of-range pixels";
}

void expect_box_occlusion(const image::FloatImage& img, render::Extent size, const std::string& what) {
  const scene::View view = box_view();
  const glm::ivec2 open = project(view, size, {-3.0f, 0.0f, 3.5f});
  const glm::ivec2 corner = project(view, size, {0.3f, 0.0f, 1.0f + 0.1f * kBoxRadius});
  auto inside = [&](glm::ivec2 p) { return p.x >= 0 && p.y >= 0 && p.x < size.width && p.y < size.height; };
  ASSERT_TRUE(inside(open) && inside(corner)) << what;
  EXPECT_GE(img.at(open.x, open.y), 0.95f) << what << ": open floor";
  EXPECT_LT(img.at(corner.x, corner.y), img.at(open.x, open.y) - 0.1f) << what << ": box/floor contact";
}

scene::View floor_view() {
  scene::View v;
  v.name = "floor";
  v.eye = {0.0f, 3.0f, 4.0f};
  v.target = {0.0f, 0.0f, -1.0f};
  v.near_plane = 0.1f;
  v.far_plane = 60.0f;
  return v;
}

image::FloatImage render_plan(render::Backend& backend, const render::PipelinePlan& plan, const scene::View& view,
                              render::Extent size, float radius, int frames, int first_frame) {
  auto p = backend.prepare(plan, size);
  for (int f = 0; f < frames; ++f) {
    render::FrameSetup s;
    s.view = &view;
    s.frame = first_frame + f;
    s.static_camera = true;
    s.radius = radius;
    backend.render(*p, s);
  }
  return backend.read_result(*p);
}

glm::ivec2 project(const scene::View& view, render::Extent size, glm::vec3 world) {
  render::FrameSetup s;
  s.view = &view;
  auto b = render::make_frame_block(s, size, size, render::ClipDepth::zero_to_one);
  glm::vec4 clip = b.proj * b.view * glm::vec4(world, 1.0f);
  glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {static_cast<int>(std::floor((ndc.x * 0.5f + 0.5f) * size.width)),
          static_cast<int>(std::floor((ndc.y * 0.5f + 0.5f) * size.height))};
}

CornerProbe corner_probe(float radius, render::Extent size) {
  CornerProbe p;
  p.view = floor_view();
  p.scene = quad_scene({kFloor, kWall}, p.view, radius);
  p.size = size;
  p.radius = radius;
  p.corner = project(p.view, size, {0.0f, 0.0f, -2.0f + 0.1f * radius});
  p.open = project(p.view, size, {0.0f, 0.0f, -2.0f + 4.0f * radius});
  for (const glm::ivec2 at : {p.corner, p.open})
    if (at.x < 0 || at.x >= size.width || at.y < 0 || at.y >= size.height)
      throw std::runtime_error("corner_probe: a probe point is off screen");
  return p;
}

ImageDiff compare(const image::FloatImage& a, const image::FloatImage& b) {
  if (a.width != b.width || a.height != b.height) throw std::runtime_error("image sizes differ");
  ImageDiff d;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    double e = std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    d.mean_abs += e;
    d.max_abs = std::max(d.max_abs, e);
  }
  d.mean_abs /= static_cast<double>(a.pixels.size());
  return d;
}

PickedVariants pick_variants(const std::vector<std::vector<std::string>>& kinds, bool with_gles) {
  std::vector<std::string> globs;
  for (const auto& kind : kinds) globs.insert(globs.end(), kind.begin(), kind.end());
  PickedVariants picked;
  picked.compiled = compile_variants(globs, with_gles);
  const auto& all = picked.compiled.space.variants;
  for (std::size_t k = 0; k < kinds.size(); ++k)
    for (const auto& glob : kinds[k]) {
      auto v = std::find_if(all.begin(), all.end(), [&](const auto& e) { return fnmatch(glob.c_str(), e.key.c_str(), 0) == 0; });
      if (v != all.end()) {
        picked.keys[static_cast<int>(k)] = v->key;
        break;
      }
    }
  return picked;
}

std::vector<std::vector<std::string>> method_kinds(const std::string& algorithm) {
  const std::string a = algorithm + "-";
  return {
      {a + "s08-p0-nrgb8-zdep-rst-d32-bno-x1-hp", a + "s08-p0-*-zdep-*-d32-bno-x1-??"},  // ??: not -zmip
      {a + "s16-p0-nrgb8-zdep-rip-d32-bsep-x1-hp", a + "s16-p0-*-zdep-*-d32-bsep-x1-hp"},
      {a + "s16-p1-noct-zdep-rst-d16-bsep-x2-mp", a + "s16-p1-*-zdep-*-d16-bsep-x2-mp",
       a + "s16-p0-*-zdep-*-d16-bsep-x2-mp"},
  };
}

}  // namespace aovar::test
