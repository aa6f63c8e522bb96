#include "trace/trace.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "analyze/analyze.h"
#include "compile/glslang_compiler.h"
#include "render/plan.h"
#include "shadergen/bindings.h"
#include "trace/instrument.h"

namespace aovar::trace {
namespace {

int program_index(const compile::CompiledSpace& compiled, const std::string& key) {
  for (std::size_t i = 0; i < compiled.space.programs.size(); ++i)
    if (compiled.space.programs[i].key == key) return static_cast<int>(i);
  throw std::runtime_error(fmt::format("trace: program {} is not in the compiled space", key));
}

// The draw's output extent (the viewport the backend gives it).
render::Extent draw_extent(const render::Draw& d, render::Extent size, double resolution) {
  const render::Extent e = d.full_resolution ? size : render::ao_extent(size, resolution);
  return {std::max(1, e.width >> d.level), std::max(1, e.height >> d.level)};
}

Window centred_window(render::Extent e, double share, int taps) {
  const int w = std::clamp(int(std::lround(e.width * share)), 1, e.width);
  const int h = std::clamp(int(std::lround(e.height * share)), 1, e.height);
  return {(e.width - w) / 2, (e.height - h) / 2, w, h, taps};
}

// Compiles the trace build of `program` for `window`; throws naming the program and glslang's first error.
std::vector<std::uint32_t> trace_build(const compile::CompiledSpace& compiled, int program, const Window& window,
                                       bool early_tests) {
  const int t = compiled.target_index(variants::Target::vulkan);
  if (t < 0) throw std::runtime_error("trace: the compiled space has no Vulkan builds (trace runs on lavapipe)");
  const compile::ProgramBuild& b = compiled.builds[t][program];
  const std::string source = instrument(b.source, window, early_tests);
  compile::CompileOutput out = compile::compile_program(source, variants::StageKind::fragment, variants::Target::vulkan);
  if (!out.ok) {
    std::string first = out.diagnostics.empty() ? "no diagnostic" : out.diagnostics.front().message;
    throw std::runtime_error(fmt::format("trace: the trace build of {} does not compile: {}",
                                         compiled.space.programs[program].key, first));
  }
  return out.spirv;
}

// The textures a draw reads, by slot. An input bound to one level of a MIP chain (ref.level >= 0) is read as
// level 0 of that view: its reads are moved to the real level afterwards (lod_offset), so that addresses are
// the chain's.
struct DrawInputs {
  std::vector<gpu::TracedTexture> textures;
  std::map<int, int> lod_offset;  // slot -> level added to every read
};

DrawInputs inputs_of(const render::PipelinePlan& plan, const render::Draw& d, render::Extent size) {
  DrawInputs in;
  for (const auto& [binding, ref] : d.inputs) {
    const render::Texture& tex = plan.textures[ref.texture];
    const render::Extent e = tex.full_resolution ? size : render::ao_extent(size, plan.resolution);
    const int slot = slot_of_binding(binding);
    in.textures.push_back({shadergen::binding::name(binding), slot, e.width, e.height, tex.levels,
                           render::format_bytes(tex.format)});
    if (ref.level > 0) in.lod_offset[slot] = ref.level;
  }
  return in;
}

gpu::FetchTrace to_trace(const render::Backend::TracedDraw& traced, const render::Draw& d, const Window& w,
                         render::Extent extent, int draw_in_pass, DrawInputs inputs) {
  gpu::FetchTrace t;
  t.pass = d.pass;
  t.draw = draw_in_pass;
  t.frame_width = extent.width;
  t.frame_height = extent.height;
  t.x0 = w.x0, t.y0 = w.y0, t.width = w.width, t.height = w.height;
  t.max_taps = w.max_taps;
  t.overflowed_pixels = traced.words.at(0);
  t.reads.assign(traced.words.begin() + 1, traced.words.end());
  if (!inputs.lod_offset.empty())
    for (std::uint32_t& word : t.reads) {
      if (word == gpu::kNoRead) continue;
      gpu::TexelRead r = gpu::unpack_read(word);
      auto it = inputs.lod_offset.find(r.slot);
      if (it == inputs.lod_offset.end()) continue;
      r.lod += it->second;
      word = gpu::pack_read(r);
    }
  t.textures = std::move(inputs.textures);
  return t;
}

}  // namespace

std::vector<int> traceable_draws(const render::PipelinePlan& plan) {
  std::vector<int> out;
  for (std::size_t i = 0; i < plan.draws.size(); ++i)
    if (!plan.draws[i].geometry && plan.draws[i].fragment >= 0) out.push_back(static_cast<int>(i));
  return out;
}

int max_taps_of(const std::vector<std::uint32_t>& spirv) {
  const analyze::ProgramCost cost = analyze::analyze_spirv(spirv);
  const int counted = int(std::ceil(cost.total_fetches()));
  return cost.has_dynamic_loop() ? 2 * counted + 16 : counted + 1;
}

std::vector<gpu::FetchTrace> trace_variant(runner::VariantRunner& runner, int variant, const scene::View& view,
                                           float radius, const TraceOptions& options, image::FloatImage* image) {
  if (runner.device().backend != "lavapipe")
    throw render::BackendError(fmt::format("trace: fetch traces run on lavapipe, not {}", runner.device().backend));
  const compile::CompiledSpace& compiled = runner.compiled();
  render::PipelinePlan plan = runner.plan(variant);
  const render::Extent size = runner.size();
  std::vector<Window> windows(plan.draws.size());
  const std::vector<int> all = traceable_draws(plan);
  for (int i : options.draws.empty() ? all : options.draws) {
    if (std::find(all.begin(), all.end(), i) == all.end())
      throw std::invalid_argument(fmt::format("trace: draw {} of {} cannot be traced", i, plan.variant));
    render::Draw& d = plan.draws[i];
    const int program = program_index(compiled, plan.shaders[d.fragment].program_key);
    const Window w = centred_window(draw_extent(d, size, plan.resolution), options.window_share,
                                    max_taps_of(plan.shaders[d.fragment].spirv));
    render::Shader traced = plan.shaders[d.fragment];
    traced.spirv = trace_build(compiled, program, w, d.depth == render::DepthUse::skip_background);
    d.fragment = static_cast<int>(plan.shaders.size());
    plan.shaders.push_back(std::move(traced));
    d.trace_words = 1 + std::int64_t(w.width) * w.height * w.max_taps;
    windows[i] = w;
  }
  auto prepared = runner.prepare(plan);
  runner.backend().render(*prepared, {&view, 0, true, radius});
  std::vector<render::Backend::TracedDraw> traced = runner.backend().read_traces(*prepared);
  if (image) *image = runner.backend().read_result(*prepared);

  // The prepared plan is the plan at this size (render::plan_for_size may drop draws into missing MIP levels):
  // match the traced draws to the plan's by name and level.
  std::vector<gpu::FetchTrace> out;
  std::map<std::string, int> draws_in_pass;
  for (const render::Backend::TracedDraw& td : traced) {
    std::size_t i = 0;
    while (i < plan.draws.size() && !(plan.draws[i].name == td.name && plan.draws[i].level == td.level)) ++i;
    if (i == plan.draws.size()) throw std::logic_error("trace: a traced draw is not in the plan: " + td.name);
    const render::Draw& d = plan.draws[i];
    out.push_back(to_trace(td, d, windows[i], draw_extent(d, size, plan.resolution), draws_in_pass[d.pass]++,
                           inputs_of(plan, d, size)));
    out.back().plan_draw = static_cast<int>(i);
  }
  return out;
}

}  // namespace aovar::trace
