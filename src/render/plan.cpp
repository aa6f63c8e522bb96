#include "render/plan.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "compile/parameters.h"
#include "render/backend.h"

namespace aovar::render {
using namespace shadergen::binding;  // kDepth, kNormal, ...: the sampler each input is bound at

std::vector<std::string> PipelinePlan::passes() const {
  std::vector<std::string> out;
  for (const auto& d : draws)
    if (std::find(out.begin(), out.end(), d.pass) == out.end()) out.push_back(d.pass);
  return out;
}

namespace {

// The pass plan's draws with the target's shaders (each program once, in order of first use) and their blocks.
class ShaderBinder {
 public:
  ShaderBinder(const compile::CompiledSpace& c, int variant, variants::Target target)
      : c_(c), entry_(c.space.variants.at(variant)), target_(target), t_(c.target_index(target)) {
    if (t_ < 0) throw std::runtime_error(fmt::format("target {} was not compiled", variants::target_name(target)));
  }

  int shader(int program, PipelinePlan& plan) {
    auto [it, fresh] = shader_of_.emplace(program, static_cast<int>(plan.shaders.size()));
    if (!fresh) return it->second;
    const compile::ProgramBuild& b = c_.builds[t_][program];
    const variants::ProgramSpec& spec = c_.space.programs[program];
    if (!b.ok) throw std::runtime_error(fmt::format("program {} did not compile", spec.key));
    Shader s;
    s.program_key = spec.key;
    s.stage = spec.stage;
    if (target_ == variants::Target::vulkan) s.spirv = b.output.spirv;
    else s.glsl = b.source;
    plan.shaders.push_back(std::move(s));
    return it->second;
  }

  Draw bind(const passplan::PassDraw& pd, PipelinePlan& plan, const ParamOverrides& overrides,
            std::set<std::string>& used) {
    Draw d;
    static_cast<passplan::DrawIo&>(d) = pd;
    const auto& programs = entry_.passes.at(pd.program_pass);
    d.vertex = shader(programs[0], plan);
    d.fragment = shader(programs[1], plan);
    d.params = compile::block_values(c_, t_, programs[1], c_.manifest.passes[pd.program_pass].name, overrides,
                                     pd.uniforms, &used);
    return d;
  }

 private:
  const compile::CompiledSpace& c_;
  const variants::VariantEntry& entry_;
  variants::Target target_;
  int t_ = -1;
  std::map<int, int> shader_of_;
};

}  // namespace

PipelinePlan plan_pipeline(const compile::CompiledSpace& compiled, int variant, variants::Target target,
                           const ParamOverrides& overrides, bool strict) {
  ShaderBinder binder(compiled, variant, target);
  const passplan::PassPlan passes = passplan::plan_passes(compiled.manifest, compiled.space, variant);
  PipelinePlan plan;
  static_cast<passplan::PlanResources&>(plan) = passes;
  std::set<std::string> used;
  for (const passplan::PassDraw& pd : passes.draws) plan.draws.push_back(binder.bind(pd, plan, overrides, used));
  for (const auto& [key, value] : overrides)
    if (strict && !used.count(key))
      throw std::runtime_error(fmt::format("parameter '{}' is not a parameter of variant {} (use <pass>.<name>, "
                                           "e.g. ao.intensity)", key, plan.variant));
  return plan;
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
  // A shared G-buffer's plan (render/gbuffer_share.h) is its geometry draw alone, with no result: the
  // variants sample it, nothing reads it back.
  const bool gbuffer_only = plan.result == -1 && plan.draws.size() == 1 && plan.draws[0].geometry;
  if (gbuffer_only) {
    validate_draw(plan, plan.draws[0], bad);
    return;
  }
  if (plan.result < 0 || plan.result >= static_cast<int>(plan.textures.size())) bad("no result texture");
  // Full resolution normally; a plan_prefix cut may end at AO resolution (read back at that size).
  if (plan.textures[plan.result].format != Format::r32f) bad("the result is not an r32f texture");
  for (const Draw& d : plan.draws) validate_draw(plan, d, bad);
}

PipelinePlan plan_for_size(const PipelinePlan& plan, Extent size) {
  PipelinePlan fit = plan;
  std::erase_if(fit.draws, [&](const Draw& d) { return !passplan::draw_runs_at(plan, d, size); });
  for (Texture& t : fit.textures) t.levels = passplan::levels_at(plan, t, size);
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
