#include "render/plan.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "render/backend.h"

namespace aovar::render {
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

std::vector<std::string> PipelinePlan::passes() const {
  std::vector<std::string> out;
  for (const auto& d : draws)
    if (std::find(out.begin(), out.end(), d.pass) == out.end()) out.push_back(d.pass);
  return out;
}

namespace {

class PlanBuilder {
 public:
  PlanBuilder(const compile::CompiledSpace& c, int variant, variants::Target target, const ParamOverrides& o,
              bool strict)
      : c_(c), entry_(c.space.variants.at(variant)), target_(target), overrides_(o), strict_(strict) {
    t_ = c.target_index(target);
    if (t_ < 0) throw std::runtime_error(fmt::format("target {} was not compiled", variants::target_name(target)));
    plan_.variant = entry_.key;
    for (int a = 0; a < variants::kAxisCount; ++a) {
      int i = entry_.point[a] >= 0 ? entry_.point[a] : 0;  // collapsed: no stage reads it, any value will do
      plan_.axes[std::string(variants::axis_info(variants::axis_at(a)).name)] =
          c.manifest.value(variants::axis_at(a), i).text;
    }
  }

  const std::string& axis(Axis a) { return plan_.axes[std::string(variants::axis_info(a).name)]; }

  // {vertex, fragment} programs of a manifest pass, or nullptr when the variant does not run it.
  const std::array<int, 2>* pass(const std::string& name) {
    for (std::size_t i = 0; i < c_.manifest.passes.size(); ++i)
      if (c_.manifest.passes[i].name == name) {
        const auto& p = entry_.passes[i];
        return p[0] == variants::kNoProgram && p[1] == variants::kNoProgram ? nullptr : &p;
      }
    return nullptr;
  }

  int shader(int program) {
    auto [it, fresh] = shader_of_.emplace(program, static_cast<int>(plan_.shaders.size()));
    if (!fresh) return it->second;
    const compile::ProgramBuild& b = c_.builds[t_][program];
    const variants::ProgramSpec& spec = c_.space.programs[program];
    if (!b.ok) throw std::runtime_error(fmt::format("program {} did not compile", spec.key));
    Shader s;
    s.program_key = spec.key;
    s.stage = spec.stage;
    if (target_ == variants::Target::vulkan) s.spirv = b.output.spirv;
    else s.glsl = b.source;
    plan_.shaders.push_back(std::move(s));
    return it->second;
  }

  // AOParams contents of a fragment program: manifest params (or overrides) by member name; members the
  // renderer sets itself come from `renderer_set`.
  std::vector<float> params(const std::string& pass_name, int program,
                            const std::map<std::string, float>& renderer_set = {}) {
    const compile::ProgramBuild& b = c_.builds[t_][program];
    const variants::ProgramSpec& spec = c_.space.programs[program];
    std::vector<float> out;
    for (const auto& member : b.output.params_block) {
      auto param = std::find_if(spec.params.begin(), spec.params.end(),
                                [&](const variants::Param& p) { return p.name == member.name; });
      if (param != spec.params.end()) {
        std::string key = pass_name + "." + member.name;
        auto o = overrides_.find(key);
        used_.insert(key);
        out.push_back(static_cast<float>(o != overrides_.end() ? o->second : param->value));
      } else if (auto r = renderer_set.find(member.name); r != renderer_set.end()) {
        out.push_back(r->second);
      } else {
        throw std::runtime_error(fmt::format("{}: AOParams member '{}' is neither a manifest parameter of pass "
                                             "'{}' nor set by the renderer", spec.key, member.name, pass_name));
      }
    }
    return out;
  }

  int texture(Texture t) {
    plan_.textures.push_back(std::move(t));
    return static_cast<int>(plan_.textures.size()) - 1;
  }

  // A fullscreen draw at AO or full resolution writing level `level` of texture `out`.
  void draw_into(const std::string& name, const std::string& pass_name, const std::string& param_pass,
                 const std::array<int, 2>& programs, std::vector<std::pair<int, TextureRef>> inputs, int out,
                 bool full_res, const std::map<std::string, float>& renderer_set = {}, int level = 0) {
    Draw d;
    d.name = name;
    d.pass = pass_name;
    d.vertex = shader(programs[0]);
    d.fragment = shader(programs[1]);
    d.params = params(param_pass, programs[1], renderer_set);
    d.inputs = std::move(inputs);
    d.outputs = {TextureRef{out, false, level}};
    d.full_resolution = full_res;
    d.level = level;
    plan_.draws.push_back(std::move(d));
  }

  // A fullscreen draw writing a fresh texture (R16F unless told), returned.
  int fullscreen(const std::string& name, const std::string& pass_name, const std::array<int, 2>& programs,
                 std::vector<std::pair<int, TextureRef>> inputs, bool full_res,
                 const std::map<std::string, float>& renderer_set = {}, bool double_buffered = false,
                 Format format = Format::r16f, const std::string& param_pass = {}) {
    int out = texture({name, format, full_res, double_buffered, false, {}});
    draw_into(name, pass_name, param_pass.empty() ? pass_name : param_pass, programs, std::move(inputs), out,
              full_res, renderer_set);
    return out;
  }

  int depth_buffer(DepthBuffer b) {
    plan_.depth_buffers.push_back(std::move(b));
    return static_cast<int>(plan_.depth_buffers.size()) - 1;
  }

  // The AO-resolution depth buffer holding 1.0 where the depth texel the AO pass reads is background, drawn
  // by the manifest's background_mask pass; -1 when the manifest has none (then nothing is skipped there).
  int background_mask(int depth) {
    const auto* mask = pass("background_mask");
    if (!mask) return -1;
    int buffer = depth_buffer({"background_mask", false});
    Draw d;
    d.name = d.pass = "background_mask";
    d.vertex = shader((*mask)[0]);
    d.fragment = shader((*mask)[1]);
    d.params = params("background_mask", (*mask)[1]);
    d.inputs = {{kDepth, TextureRef{depth}}};
    d.full_resolution = false;
    d.depth = DepthUse::write_mask;
    d.depth_buffer = buffer;
    plan_.draws.push_back(std::move(d));
    return buffer;
  }

  // The last draw rejects background pixels before shading (plan.h): its outputs start each frame at 1, the
  // value its shader's early-out writes there. buffer -1: no mask at this resolution, the draw stays as is.
  void skip_background(int buffer) {
    if (buffer < 0) return;
    Draw& d = plan_.draws.back();
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
  int prefilter(int depth, bool full_ao) {
    if (const auto* blur = pass("unsharp_blur")) {
      // The depth Gaussian in two 1-D draws; r32f because the AO pass subtracts it from depth.
      int h = fullscreen("depth_blur.h", "prefilter", *blur, {{kDepth, TextureRef{depth}}}, full_ao, {{"axis", 0.0f}},
                         false, Format::r32f, "unsharp_blur");
      return fullscreen("depth_blur", "prefilter", *blur, {{kDepth, TextureRef{depth}}, {kPrefilter, TextureRef{h}}},
                        full_ao, {{"axis", 1.0f}}, false, Format::r32f, "unsharp_blur");
    }
    // SAO's pyramid, or the same pyramid for the far taps of a depth_mip = on variant (pass depth_mip).
    for (const char* name : {"zmip", "depth_mip"})
      if (const auto* zmip = pass(name)) {
        // Level 0 converts depth to camera-space z; level l + 1 subsamples level l (McGuire et al. 2012, §2.2, table 1).
        Texture t{"zmip", Format::r32f, full_ao, false, false, {}};
        t.levels = kZmipLevels;
        int z = texture(t);
        for (int level = 0; level < kZmipLevels; ++level) {
          std::vector<std::pair<int, TextureRef>> inputs = {{kDepth, TextureRef{depth}}};
          if (level > 0) inputs.push_back({kPrefilter, TextureRef{z, false, level - 1}});
          draw_into(fmt::format("zmip.{}", level), "prefilter", name, *zmip, inputs, z, full_ao,
                    {{"level", float(level)}}, level);
        }
        return z;
      }
    if (axis(Axis::depth_mip) == "on")
      throw std::runtime_error(plan_.variant + ": depth_mip = on but the manifest has no depth_mip pass to build "
                               "the z pyramid its taps read (shader_src/aovar.toml, [passes.depth_mip])");
    return -1;
  }

  PipelinePlan build() {
    plan_.resolution = std::stod(axis(Axis::resolution));
    plan_.progressive = axis(Axis::progressive) == "true";
    bool full_ao = plan_.resolution >= 1.0;

    // G-buffer.
    const auto* gbuffer = pass("gbuffer");
    if (!gbuffer) throw std::runtime_error(plan_.variant + ": the manifest has no gbuffer pass");
    Format depth_format = axis(Axis::depth_format) == "r16f" ? Format::r16f : Format::r32f;
    int depth = texture({"depth", depth_format, true, false, true, {kClearFar, 0, 0, 0}});
    int normal = -1, position = -1;
    const std::string& normals = axis(Axis::normals);
    if (normals != "depth")  // rgb8 is stored RGBA8: no API guarantees a renderable 24-bit format
      normal = texture({"normal", normals == "rgb8" ? Format::rgba8 : Format::rg8, true, false, true, {}});
    if (axis(Axis::position) == "position")
      position = texture({"position", Format::rgba32f, true, false, true, {0, 0, kClearNegFar, 0}});
    Draw g;
    g.name = g.pass = "gbuffer";
    g.geometry = true;
    g.vertex = shader((*gbuffer)[0]);
    g.fragment = shader((*gbuffer)[1]);
    g.params = params("gbuffer", (*gbuffer)[1]);
    g.outputs = {TextureRef{depth}, TextureRef{normal}, TextureRef{position}};
    while (!g.outputs.empty() && g.outputs.back().texture < 0) g.outputs.pop_back();
    g.depth = DepthUse::geometry;
    const int zbuffer = g.depth_buffer = depth_buffer({"zbuffer", true});
    plan_.draws.push_back(std::move(g));
    // Where background pixels are rejected before shading, at AO resolution (full: the G-buffer's depth).
    const int ao_skip = full_ao ? zbuffer : background_mask(depth);

    // AO at its resolution; progressive variants keep both halves (double-buffered by frame parity).
    const auto* ao = pass("ao");
    if (!ao) throw std::runtime_error(plan_.variant + ": the manifest has no ao pass");
    std::vector<std::pair<int, TextureRef>> gbuffer_inputs = {{kDepth, TextureRef{depth}}};
    if (normal >= 0) gbuffer_inputs.push_back({kNormal, TextureRef{normal}});
    if (position >= 0) gbuffer_inputs.push_back({kPosition, TextureRef{position}});
    int pre = prefilter(depth, full_ao);
    if (pre >= 0) gbuffer_inputs.push_back({kPrefilter, TextureRef{pre}});
    // Methods that pack a depth key next to AO (SAO) blur with blur_keyed and carry the key in rgba8.
    const auto* keyed = pass("blur_keyed");
    Format ao_format = keyed ? Format::rgba8 : Format::r16f;
    int current = fullscreen("ao", "ao", *ao, gbuffer_inputs, full_ao, {}, plan_.progressive, ao_format);
    skip_background(ao_skip);

    if (plan_.progressive) {
      const auto* prog = pass("progressive");
      if (!prog) throw std::runtime_error(plan_.variant + ": progressive variant but no progressive pass");
      current = fullscreen("progressive", "progressive", *prog,
                           {{kInput, TextureRef{current}}, {kHistory, TextureRef{current, true}}}, full_ao, {}, false,
                           ao_format);
      skip_background(ao_skip);
    }

    // The passes after AO read depth and the AO chain so far.
    auto depth_and = [&](int input) {
      return std::vector<std::pair<int, TextureRef>>{{kDepth, TextureRef{depth}}, {kInput, TextureRef{input}}};
    };
    const char* blur_pass = keyed ? "blur_keyed" : "blur";
    // The keyed blurs take background from the key and write it back: their output there is not a constant.
    const int blur_skip = keyed ? -1 : ao_skip;
    if (const auto* blur = keyed ? keyed : pass("blur")) {
      if (axis(Axis::blur) == "separable") {
        current = fullscreen("blur.h", "blur", *blur, depth_and(current), full_ao,
                             {{"axis", 0.0f}}, false, ao_format, blur_pass);
        skip_background(blur_skip);
        current = fullscreen("blur.v", "blur", *blur, depth_and(current), full_ao,
                             {{"axis", 1.0f}}, false, ao_format, blur_pass);
        skip_background(blur_skip);
      } else {
        current = fullscreen("blur", "blur", *blur, depth_and(current), full_ao, {},
                             false, ao_format, blur_pass);
        skip_background(blur_skip);
      }
    }

    if (!full_ao) {
      const auto* up = pass("upsample");
      if (!up) throw std::runtime_error(plan_.variant + ": reduced resolution but no upsample pass");
      current = fullscreen("upsample", "upsample", *up, depth_and(current), true);
      skip_background(zbuffer);
    }

    plan_.textures[current].format = Format::r32f;  // the result: NaN and Inf survive the read-back
    plan_.result = current;
    for (const auto& [key, value] : overrides_)
      if (strict_ && !used_.count(key))
        throw std::runtime_error(fmt::format("parameter '{}' is not a parameter of variant {} (use <pass>.<name>, "
                                             "e.g. ao.intensity)", key, plan_.variant));
    return std::move(plan_);
  }

 private:
  const compile::CompiledSpace& c_;
  const variants::VariantEntry& entry_;
  variants::Target target_;
  const ParamOverrides& overrides_;
  bool strict_ = true;
  int t_ = -1;
  PipelinePlan plan_;
  std::map<int, int> shader_of_;
  std::set<std::string> used_;
};

}  // namespace

PipelinePlan plan_pipeline(const compile::CompiledSpace& compiled, int variant, variants::Target target,
                           const ParamOverrides& overrides, bool strict) {
  return PlanBuilder(compiled, variant, target, overrides, strict).build();
}

std::vector<std::string> parameter_keys(const compile::CompiledSpace& compiled, int variant) {
  std::vector<std::string> keys;
  const auto& entry = compiled.space.variants.at(variant);
  for (std::size_t i = 0; i < compiled.manifest.passes.size(); ++i)
    for (int program : entry.passes[i])
      if (program >= 0)
        for (const auto& param : compiled.space.programs[program].params)
          keys.push_back(compiled.manifest.passes[i].name + "." + param.name);
  return keys;
}

PipelinePlan plan_prefix(const PipelinePlan& plan, const std::string& last_draw) {
  auto it = std::find_if(plan.draws.begin(), plan.draws.end(), [&](const Draw& d) { return d.name == last_draw; });
  if (it == plan.draws.end()) throw std::runtime_error(plan.variant + ": no draw named '" + last_draw + "'");
  PipelinePlan cut = plan;
  cut.draws.erase(cut.draws.begin() + (it - plan.draws.begin()) + 1, cut.draws.end());
  int out = cut.draws.back().outputs.at(0).texture;
  cut.textures[out].format = Format::r32f;
  cut.textures[out].double_buffered = false;
  cut.result = out;
  return cut;
}

namespace {

// The checks of validate_plan on one draw; `bad` throws.
template <class Bad>
void validate_draw(const PipelinePlan& plan, const Draw& d, const Bad& bad) {
  const int nt = static_cast<int>(plan.textures.size()), ns = static_cast<int>(plan.shaders.size());
  const int nz = static_cast<int>(plan.depth_buffers.size());
  if (d.vertex < 0 || d.vertex >= ns || d.fragment < 0 || d.fragment >= ns)
    bad(fmt::format("draw {} names no shader", d.name));
  if (d.outputs.empty() && d.depth != DepthUse::write_mask) bad(fmt::format("draw {} has no outputs", d.name));
  if ((d.depth != DepthUse::none) != (d.depth_buffer >= 0) || d.depth_buffer >= nz)
    bad(fmt::format("draw {} uses depth {} with depth buffer {} of {}", d.name, depth_use_name(d.depth),
                    d.depth_buffer, nz));
  if (d.geometry && d.depth != DepthUse::geometry) bad(fmt::format("geometry draw {} has no depth test", d.name));
  if (d.depth_buffer >= 0 && (plan.depth_buffers[d.depth_buffer].full_resolution != d.full_resolution || d.level != 0))
    bad(fmt::format("draw {} tests a depth buffer of another size", d.name));
  for (const TextureRef& o : d.outputs) {
    if (o.texture >= nt) bad(fmt::format("draw {} writes texture {}", d.name, o.texture));
    if (o.texture < 0) continue;  // location unused
    const Texture& t = plan.textures[o.texture];
    if (o.previous) bad(fmt::format("draw {} writes the previous copy of {}", d.name, t.name));
    if (t.full_resolution != d.full_resolution)
      bad(fmt::format("draw {} writes {} at another resolution", d.name, t.name));
    if (std::max(o.level, 0) != d.level || d.level >= t.levels)
      bad(fmt::format("draw {} writes level {} of {} ({} levels) at viewport level {}", d.name, o.level, t.name,
                      t.levels, d.level));
    // Reading another MIP level of the texture being written is fine: the views do not overlap.
    for (const auto& [binding, in] : d.inputs)
      if (in.texture == o.texture && !in.previous && (in.level < 0 || in.level == d.level))
        bad(fmt::format("draw {} reads the texture it writes", d.name));
  }
  for (const auto& [binding, in] : d.inputs) {
    if (!is_sampler(binding))
      bad(fmt::format("draw {} binds a texture at binding {} ({}..{} only)", d.name, binding, kFirstSampler,
                      kCount - 1));
    if (in.texture < 0 || in.texture >= nt) bad(fmt::format("draw {} reads texture {}", d.name, in.texture));
    if (in.level >= plan.textures[in.texture].levels)
      bad(fmt::format("draw {} reads level {} of {}", d.name, in.level, plan.textures[in.texture].name));
  }
}

}  // namespace

void validate_plan(const PipelinePlan& plan, std::string_view backend) {
  auto bad = [&](const std::string& what) {
    throw BackendError(fmt::format("{}: plan of {} is malformed: {}", backend, plan.variant, what));
  };
  if (plan.draws.empty()) bad("no draws");
  if (plan.result < 0 || plan.result >= static_cast<int>(plan.textures.size())) bad("no result texture");
  // Full resolution normally; a plan_prefix cut may end at AO resolution (read back at that size).
  if (plan.textures[plan.result].format != Format::r32f) bad("the result is not an r32f texture");
  for (const Draw& d : plan.draws) validate_draw(plan, d, bad);
}

PipelinePlan plan_for_size(const PipelinePlan& plan, Extent size) {
  PipelinePlan fit = plan;
  const Extent ao = ao_extent(size, plan.resolution);
  for (Texture& t : fit.textures) {
    const Extent e = t.full_resolution ? size : ao;
    int possible = 1;
    while ((std::max(e.width, e.height) >> possible) > 0) ++possible;
    t.levels = std::min(t.levels, possible);
  }
  std::erase_if(fit.draws, [&](const Draw& d) {
    return std::any_of(d.outputs.begin(), d.outputs.end(),
                       [&](const TextureRef& o) { return o.texture >= 0 && d.level >= fit.textures[o.texture].levels; });
  });
  return fit;
}

std::size_t draw_index_at_size(const PipelinePlan& plan, Extent size, std::string_view name) {
  const PipelinePlan ran = plan_for_size(plan, size);
  const auto it = std::find_if(ran.draws.begin(), ran.draws.end(), [&](const Draw& d) { return d.name == name; });
  if (it == ran.draws.end())
    throw std::runtime_error(fmt::format("{}: no {} draw at {}x{}", plan.variant, name, size.width, size.height));
  return static_cast<std::size_t>(it - ran.draws.begin());
}

PipelinePlan plan_without_background_skip(const PipelinePlan& plan) {
  PipelinePlan all = plan;
  std::erase_if(all.draws, [](const Draw& d) { return d.depth == DepthUse::write_mask; });
  std::vector<bool> used(all.depth_buffers.size(), false);
  for (Draw& d : all.draws) {
    if (d.depth == DepthUse::skip_background) {
      d.depth = DepthUse::none;
      d.depth_buffer = -1;
      for (const TextureRef& out : d.outputs)
        if (out.texture >= 0) all.textures[out.texture].cleared = false;  // fullscreen outputs: rewritten anyway
    }
    if (d.depth_buffer >= 0) used[d.depth_buffer] = true;
  }
  std::vector<int> index(all.depth_buffers.size(), -1);
  std::vector<DepthBuffer> kept;
  for (std::size_t b = 0; b < all.depth_buffers.size(); ++b)
    if (used[b]) {
      index[b] = static_cast<int>(kept.size());
      kept.push_back(all.depth_buffers[b]);
    }
  all.depth_buffers = std::move(kept);
  for (Draw& d : all.draws)
    if (d.depth_buffer >= 0) d.depth_buffer = index[d.depth_buffer];
  return all;
}

PipelinePlan plan_single_frame(const PipelinePlan& plan) {
  PipelinePlan one = plan;
  for (Draw& d : one.draws) {
    if (d.name != "progressive") continue;
    TextureRef current{};
    for (const auto& [binding, ref] : d.inputs)
      if (binding == kInput) current = ref;
    for (auto& [binding, ref] : d.inputs)
      if (binding == kHistory) ref = current;
  }
  return one;
}

}  // namespace aovar::render
