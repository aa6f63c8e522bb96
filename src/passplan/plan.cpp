#include "passplan/plan.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "shadergen/bindings.h"

namespace aovar::passplan {
using variants::Axis;
using namespace shadergen::binding;  // kDepth, kNormal, ...: the sampler each input is bound at

const char* format_name(Format f) {
  switch (f) {
    case Format::r16f: return "r16f";
    case Format::r32f: return "r32f";
    case Format::rgba8: return "rgba8";
    case Format::rg8: return "rg8";
    case Format::rgba32f: return "rgba32f";
  }
  return "?";
}

int format_bytes(Format f) {
  switch (f) {
    case Format::r16f: return 2;
    case Format::r32f: return 4;
    case Format::rgba8: return 4;
    case Format::rg8: return 2;
    case Format::rgba32f: return 16;
  }
  return 0;
}

const char* depth_use_name(DepthUse u) {
  switch (u) {
    case DepthUse::none: return "none";
    case DepthUse::geometry: return "geometry";
    case DepthUse::write_mask: return "write_mask";
    case DepthUse::skip_background: return "skip_background";
  }
  return "?";
}

int levels_at(const PlanResources& plan, const Texture& t, Extent full) {
  return std::min(t.levels, mip_levels_at(t.full_resolution ? full : ao_extent(full, plan.resolution)));
}

bool draw_runs_at(const PlanResources& plan, const DrawIo& d, Extent full) {
  return std::none_of(d.outputs.begin(), d.outputs.end(), [&](const TextureRef& o) {
    return o.texture >= 0 && d.level >= levels_at(plan, plan.textures[o.texture], full);
  });
}

namespace {

using Inputs = std::vector<std::pair<int, TextureRef>>;

class PassPlanner {
 public:
  PassPlanner(const variants::Manifest& m, const variants::VariantSpace& space, int variant)
      : m_(m), entry_(space.variants.at(variant)) {
    plan_.variant = entry_.key;
    for (int a = 0; a < variants::kAxisCount; ++a) {
      int i = entry_.point[a] >= 0 ? entry_.point[a] : 0;  // collapsed: no stage reads it, any value will do
      plan_.axes[std::string(variants::axis_info(variants::axis_at(a)).name)] = m.value(variants::axis_at(a), i).text;
    }
  }

  PassPlan build();

 private:
  const std::string& axis(Axis a) { return plan_.axes[std::string(variants::axis_info(a).name)]; }

  // The index of manifest pass `name` when the variant runs it, else -1.
  int pass(const std::string& name) const {
    for (std::size_t i = 0; i < m_.passes.size(); ++i)
      if (m_.passes[i].name == name) {
        const auto& p = entry_.passes[i];
        return p[0] == variants::kNoProgram && p[1] == variants::kNoProgram ? -1 : static_cast<int>(i);
      }
    return -1;
  }
  int required_pass(const std::string& name, const char* why) const {
    int p = pass(name);
    if (p < 0) throw std::runtime_error(plan_.variant + ": " + why);
    return p;
  }

  int texture(Texture t) {
    plan_.textures.push_back(std::move(t));
    return static_cast<int>(plan_.textures.size()) - 1;
  }
  int depth_buffer(DepthBuffer b) {
    plan_.depth_buffers.push_back(std::move(b));
    return static_cast<int>(plan_.depth_buffers.size()) - 1;
  }

  // A fullscreen draw of manifest pass `program_pass` at AO or full resolution writing level `level` of `out`.
  void draw_into(const std::string& name, const std::string& group, int program_pass, Inputs inputs, int out,
                 bool full_res, std::vector<Uniform> uniforms = {}, int level = 0) {
    PassDraw d;
    d.name = name;
    d.pass = group;
    d.program_pass = program_pass;
    d.uniforms = std::move(uniforms);
    d.inputs = std::move(inputs);
    d.outputs = {TextureRef{out, false, level}};
    d.full_resolution = full_res;
    d.level = level;
    plan_.draws.push_back(std::move(d));
  }

  // A fullscreen draw writing a fresh texture (R16F unless told), returned.
  int fullscreen(const std::string& name, const std::string& group, int program_pass, Inputs inputs, bool full_res,
                 std::vector<Uniform> uniforms = {}, bool double_buffered = false, Format format = Format::r16f) {
    int out = texture({name, format, full_res, double_buffered, false, {}});
    draw_into(name, group, program_pass, std::move(inputs), out, full_res, std::move(uniforms));
    return out;
  }

  int background_mask(int depth);
  void skip_background(int buffer);
  int prefilter(int depth, bool full_ao);
  struct Gbuffer {
    int depth = -1, normal = -1, position = -1;  // textures (normal, position: -1 when the variant has none)
    int zbuffer = -1;                            // its depth buffer
  };
  Gbuffer gbuffer();

  const variants::Manifest& m_;
  const variants::VariantEntry& entry_;
  PassPlan plan_;
};

// The AO-resolution depth buffer holding 1.0 where the depth texel the AO pass reads is background, drawn
// by the manifest's background_mask pass; -1 when the manifest has none (then nothing is skipped there).
int PassPlanner::background_mask(int depth) {
  const int mask = pass("background_mask");
  if (mask < 0) return -1;
  int buffer = depth_buffer({"background_mask", false});
  PassDraw d;
  d.name = d.pass = "background_mask";
  d.program_pass = mask;
  d.inputs = {{kDepth, TextureRef{depth}}};
  d.full_resolution = false;
  d.depth = DepthUse::write_mask;
  d.depth_buffer = buffer;
  plan_.draws.push_back(std::move(d));
  return buffer;
}

// The last draw rejects background pixels before shading (plan.h): its outputs start each frame at 1, the
// value its shader's early-out writes there. buffer -1: no mask at this resolution, the draw stays as is.
void PassPlanner::skip_background(int buffer) {
  if (buffer < 0) return;
  DrawIo& d = plan_.draws.back();
  d.depth = DepthUse::skip_background;
  d.depth_buffer = buffer;
  for (const TextureRef& out : d.outputs) {
    plan_.textures[out.texture].cleared = true;
    plan_.textures[out.texture].clear = {1, 1, 1, 1};
  }
}

// Method-specific inputs of the AO pass (plan.h): the texture bound at kPrefilter, or -1. The passes are named
// here because the renderer draws them: a method with a prefilter pass of its own is the one kind that touches
// the source (docs/architecture.md, "Where a new AO method goes").
int PassPlanner::prefilter(int depth, bool full_ao) {
  if (const int blur = pass("unsharp_blur"); blur >= 0) {
    // The depth Gaussian in two 1-D draws; r32f because the AO pass subtracts it from depth.
    int h = fullscreen("depth_blur.h", "prefilter", blur, {{kDepth, TextureRef{depth}}}, full_ao, {{"axis", 0.0f}},
                       false, Format::r32f);
    return fullscreen("depth_blur", "prefilter", blur, {{kDepth, TextureRef{depth}}, {kPrefilter, TextureRef{h}}},
                      full_ao, {{"axis", 1.0f}}, false, Format::r32f);
  }
  // SAO's pyramid, or the same pyramid for the far taps of a depth_mip = on variant (pass depth_mip).
  for (const char* name : {"zmip", "depth_mip"})
    if (const int zmip = pass(name); zmip >= 0) {
      // Level 0 converts depth to camera-space z; level l + 1 subsamples level l (McGuire et al. 2012, §2.2, table 1).
      Texture t{"zmip", Format::r32f, full_ao, false, false, {}};
      t.levels = kZmipLevels;
      int z = texture(t);
      for (int level = 0; level < kZmipLevels; ++level) {
        Inputs inputs = {{kDepth, TextureRef{depth}}};
        if (level > 0) inputs.push_back({kPrefilter, TextureRef{z, false, level - 1}});
        draw_into(fmt::format("zmip.{}", level), "prefilter", zmip, inputs, z, full_ao, {{"level", float(level)}},
                  level);
      }
      return z;
    }
  if (axis(Axis::depth_mip) == "on")
    throw std::runtime_error(plan_.variant + ": depth_mip = on but the manifest has no depth_mip pass to build "
                             "the z pyramid its taps read (shader_src/aovar.toml, [passes.depth_mip])");
  return -1;
}

// The G-buffer draw and its targets.
PassPlanner::Gbuffer PassPlanner::gbuffer() {
  const int program_pass = required_pass("gbuffer", "the manifest has no gbuffer pass");
  Gbuffer g;
  Format depth_format = axis(Axis::depth_format) == "r16f" ? Format::r16f : Format::r32f;
  g.depth = texture({"depth", depth_format, true, false, true, {kClearFar, 0, 0, 0}});
  const std::string& normals = axis(Axis::normals);
  if (normals != "depth")  // rgb8 is stored RGBA8: no API guarantees a renderable 24-bit format
    g.normal = texture({"normal", normals == "rgb8" ? Format::rgba8 : Format::rg8, true, false, true, {}});
  if (axis(Axis::position) == "position")
    g.position = texture({"position", Format::rgba32f, true, false, true, {0, 0, kClearNegFar, 0}});
  PassDraw d;
  d.name = d.pass = "gbuffer";
  d.program_pass = program_pass;
  d.geometry = true;
  d.outputs = {TextureRef{g.depth}, TextureRef{g.normal}, TextureRef{g.position}};
  while (!d.outputs.empty() && d.outputs.back().texture < 0) d.outputs.pop_back();
  d.depth = DepthUse::geometry;
  g.zbuffer = d.depth_buffer = depth_buffer({"zbuffer", true});
  plan_.draws.push_back(std::move(d));
  return g;
}

PassPlan PassPlanner::build() {
  plan_.resolution = std::stod(axis(Axis::resolution));
  plan_.progressive = axis(Axis::progressive) == "true";
  const bool full_ao = plan_.resolution >= 1.0;

  const Gbuffer g = gbuffer();
  const int depth = g.depth, zbuffer = g.zbuffer;
  // Where background pixels are rejected before shading, at AO resolution (full: the G-buffer's depth).
  const int ao_skip = full_ao ? zbuffer : background_mask(depth);

  // AO at its resolution; progressive variants keep both halves (double-buffered by frame parity).
  const int ao = required_pass("ao", "the manifest has no ao pass");
  Inputs gbuffer_inputs = {{kDepth, TextureRef{depth}}};
  if (g.normal >= 0) gbuffer_inputs.push_back({kNormal, TextureRef{g.normal}});
  if (g.position >= 0) gbuffer_inputs.push_back({kPosition, TextureRef{g.position}});
  if (int pre = prefilter(depth, full_ao); pre >= 0) gbuffer_inputs.push_back({kPrefilter, TextureRef{pre}});
  // Methods that pack a depth key next to AO (SAO) blur with blur_keyed and carry the key in rgba8.
  const int keyed = pass("blur_keyed");
  const Format ao_format = keyed >= 0 ? Format::rgba8 : Format::r16f;
  int current = fullscreen("ao", "ao", ao, gbuffer_inputs, full_ao, {}, plan_.progressive, ao_format);
  skip_background(ao_skip);

  if (plan_.progressive) {
    const int prog = required_pass("progressive", "progressive variant but no progressive pass");
    current = fullscreen("progressive", "progressive", prog,
                         {{kInput, TextureRef{current}}, {kHistory, TextureRef{current, true}}}, full_ao, {}, false,
                         ao_format);
    skip_background(ao_skip);
  }

  // The passes after AO read depth and the AO chain so far.
  auto depth_and = [&](int input) { return Inputs{{kDepth, TextureRef{depth}}, {kInput, TextureRef{input}}}; };
  // The keyed blurs take background from the key and write it back: their output there is not a constant.
  const int blur_skip = keyed >= 0 ? -1 : ao_skip;
  if (const int blur = keyed >= 0 ? keyed : pass("blur"); blur >= 0) {
    if (axis(Axis::blur) == "separable") {
      current = fullscreen("blur.h", "blur", blur, depth_and(current), full_ao, {{"axis", 0.0f}}, false, ao_format);
      skip_background(blur_skip);
      current = fullscreen("blur.v", "blur", blur, depth_and(current), full_ao, {{"axis", 1.0f}}, false, ao_format);
      skip_background(blur_skip);
    } else {
      current = fullscreen("blur", "blur", blur, depth_and(current), full_ao, {}, false, ao_format);
      skip_background(blur_skip);
    }
  }

  if (!full_ao) {
    const int up = required_pass("upsample", "reduced resolution but no upsample pass");
    current = fullscreen("upsample", "upsample", up, depth_and(current), true);
    skip_background(zbuffer);
  }

  plan_.textures[current].format = Format::r32f;  // the result: NaN and Inf survive the read-back
  plan_.result = current;
  return std::move(plan_);
}

}  // namespace

PassPlan plan_passes(const variants::Manifest& manifest, const variants::VariantSpace& space, int variant) {
  return PassPlanner(manifest, space, variant).build();
}

}  // namespace aovar::passplan
