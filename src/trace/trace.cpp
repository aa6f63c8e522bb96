#include "trace/trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "analyze/analyze.h"
#include "compile/glslang_compiler.h"
#include "render/backend.h"
#include "render/plan.h"
#include "shadergen/bindings.h"
#include "trace/instrument.h"

namespace aovar::trace {
namespace {

// Words of one draw's storage buffer in one band: 2^27 bytes, the maxStorageBufferRange every Vulkan device
// must offer (lavapipe offers exactly that; named here, as below, because tracing is lavapipe's own).
constexpr std::int64_t kBandWords = (std::int64_t(1) << 27) / 4;

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
  if (t < 0)
    throw std::runtime_error(fmt::format("trace: the compiled space has no Vulkan builds (trace runs on {})",
                                         render::backend_for(variants::Target::vulkan)));
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

// An empty trace of draw `d` over window `w` (every slot kNoRead), to be filled band by band.
gpu::FetchTrace empty_trace(const render::Draw& d, const Window& w, render::Extent extent, DrawInputs inputs) {
  gpu::FetchTrace t;
  t.pass = d.pass;
  t.frame_width = extent.width;
  t.frame_height = extent.height;
  t.x0 = w.x0, t.y0 = w.y0, t.width = w.width, t.height = w.height;
  t.max_taps = w.max_taps;
  t.reads.assign(std::size_t(w.width) * w.height * w.max_taps, gpu::kNoRead);
  t.textures = std::move(inputs.textures);
  return t;
}

// Copies one band's storage-buffer words (overflow count, then the band's rows) into the trace, moving reads
// of inputs bound to one level of a chain to that level, and keeping every read inside its level as
// max(1, extent >> level) counts it (lavapipe's textureSize can report a level one texel larger at odd
// sizes, so a template's own clamp may let a read one texel past the edge through).
void fill_band(gpu::FetchTrace& t, const Window& band, std::span<const std::uint32_t> words,
               const std::map<int, int>& lod_offset) {
  if (words.empty()) throw std::logic_error("trace: a traced draw came back without its overflow count");
  t.overflowed_pixels += words[0];
  const std::size_t offset = std::size_t(band.y0 - t.y0) * t.width * t.max_taps;
  if (offset + words.size() - 1 > t.reads.size())
    throw std::logic_error("trace: a band's words run past its trace's reads");
  // Per slot (3 bits: at most 8), looked up once: a band holds tens of millions of reads.
  std::array<int, 8> add_lod{}, width{}, height{};
  width.fill(-1);
  for (const auto& [slot, levels] : lod_offset) add_lod.at(std::size_t(slot)) = levels;
  for (const gpu::TracedTexture& tex : t.textures) {
    width.at(std::size_t(tex.slot)) = tex.width;
    height.at(std::size_t(tex.slot)) = tex.height;
  }
  for (std::size_t k = 0; k + 1 < words.size(); ++k) {  // one pass: copied and moved together
    const std::uint32_t word = words[k + 1];
    std::uint32_t& out = t.reads[offset + k];
    if (word == gpu::kNoRead) {
      out = word;
      continue;
    }
    gpu::TexelRead r = gpu::unpack_read(word);
    r.lod += add_lod[std::size_t(r.slot)];
    if (const int w = width[std::size_t(r.slot)]; w >= 0) {
      r.x = std::min(r.x, std::max(1, w >> r.lod) - 1);
      r.y = std::min(r.y, std::max(1, height[std::size_t(r.slot)] >> r.lod) - 1);
    }
    out = gpu::pack_read(r);
  }
}

// Whether a draw after `draw` in `plan` reads a texture `draw` writes.
bool read_later(const render::PipelinePlan& plan, std::size_t draw) {
  for (const render::TextureRef& out : plan.draws[draw].outputs)
    for (std::size_t later = draw + 1; later < plan.draws.size(); ++later)
      for (const auto& [binding, in] : plan.draws[later].inputs)
        if (out.texture >= 0 && in.texture == out.texture) return true;
  return false;
}

// Rows [b * h / n, (b + 1) * h / n) of window w: band b of n.
Window band_of(const Window& w, int b, int n) {
  const int first = int(std::int64_t(w.height) * b / n), last = int(std::int64_t(w.height) * (b + 1) / n);
  return {w.x0, w.y0 + first, w.width, last - first, w.max_taps};
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

namespace {

// A dynamic loop's reads are not counted by the analyser (one trip), so its first guess of slots can be short: a
// pixel whose reads overflow is traced again with twice the slots, up to this many (the 2-D bilateral blur at
// the manifest's largest radius reads (2 x 8 + 1)^2 taps of two textures: 578).
constexpr int kMaxTraceTaps = 1024;

// One trace of `draws` (plan draw indices) with their windows, band by band: each draw's window cut into the same
// number of row bands, so that every storage buffer fits the range every Vulkan device offers; each band one
// render with its trace builds. Fills `traces` (plan draw -> trace; a draw traced again replaces its old trace).
void trace_draws(runner::VariantRunner& runner, const render::PipelinePlan& plan, const std::vector<int>& draws,
                 const std::vector<Window>& windows, const scene::View& view, float radius,
                 std::map<int, gpu::FetchTrace>& traces, image::FloatImage* image) {
  const compile::CompiledSpace& compiled = runner.compiled();
  const render::Extent size = runner.size();
  int bands = 1;
  for (int i : draws) {
    const std::int64_t row_words = std::int64_t(windows[i].width) * windows[i].max_taps;
    bands = std::max<int>(bands, int((windows[i].height * row_words + kBandWords - 2) / (kBandWords - 1)));
  }
  // Without an image to return, the draws after the last traced one need not run (no traced draw reads them;
  // the result texture stays unwritten, unread), and a traced draw no later draw reads shades its band alone.
  render::PipelinePlan ran = plan;
  if (!image && !draws.empty()) ran.draws.resize(std::size_t(*std::max_element(draws.begin(), draws.end())) + 1);
  std::set<int> fresh_draws;
  for (int b = 0; b < bands; ++b) {
    render::PipelinePlan banded = ran;
    for (int i : draws) {
      render::Draw& d = banded.draws[i];
      const Window w = band_of(windows[i], b, bands);
      if (w.height <= 0) continue;  // a small draw (a deep MIP level) has fewer rows than there are bands
      render::Shader traced = banded.shaders[d.fragment];
      traced.spirv = trace_build(compiled, program_index(compiled, traced.program_key), w,
                                 d.depth == render::DepthUse::skip_background);
      d.fragment = static_cast<int>(banded.shaders.size());
      banded.shaders.push_back(std::move(traced));
      d.trace_words = 1 + std::int64_t(w.width) * w.height * w.max_taps;
      if (!image && !read_later(ran, std::size_t(i))) d.scissor = {w.x0, w.y0, w.width, w.height};
    }
    auto prepared = runner.prepare(banded);
    runner.backend().render(*prepared, {&view, 0, true, radius});
    if (image && b == 0) *image = runner.backend().read_result(*prepared);
    // The prepared plan is the plan at this size (render::plan_for_size may drop draws into missing MIP levels):
    // the traced draws are matched to the plan's by name and level.
    for (const render::Backend::TracedDraw& td : runner.backend().read_traces(*prepared)) {
      std::size_t i = 0;
      while (i < plan.draws.size() && !(plan.draws[i].name == td.name && plan.draws[i].level == td.level)) ++i;
      if (i == plan.draws.size()) throw std::logic_error("trace: a traced draw is not in the plan: " + td.name);
      const render::Draw& d = plan.draws[i];
      DrawInputs inputs = inputs_of(plan, d, size);
      if (fresh_draws.insert(int(i)).second)
        traces[int(i)] = empty_trace(d, windows[i], draw_extent(d, size, plan.resolution), inputs);
      fill_band(traces[int(i)], band_of(windows[i], b, bands), td.words, inputs.lod_offset);
    }
  }
}

}  // namespace

std::vector<gpu::FetchTrace> trace_variant(runner::VariantRunner& runner, int variant, const scene::View& view,
                                           float radius, const TraceOptions& options, image::FloatImage* image) {
  // Trace builds are Vulkan SPIR-V with a storage buffer per draw (Backend::read_traces).
  if (render::target_of(runner.device().backend) != variants::Target::vulkan)
    throw render::BackendError(fmt::format("trace: fetch traces run on {}, not {}",
                                           render::backend_for(variants::Target::vulkan), runner.device().backend));
  const render::PipelinePlan plan = runner.plan(variant);
  const render::Extent size = runner.size();
  const std::vector<int> all = traceable_draws(plan);
  std::vector<int> draws = options.draws.empty() ? all : options.draws;
  std::vector<Window> windows(plan.draws.size());
  for (int i : draws) {
    if (std::find(all.begin(), all.end(), i) == all.end())
      throw std::invalid_argument(fmt::format("trace: draw {} of {} cannot be traced", i, plan.variant));
    const render::Draw& d = plan.draws[i];
    windows[i] = centred_window(draw_extent(d, size, plan.resolution), options.window_share,
                                max_taps_of(plan.shaders[d.fragment].spirv));
  }
  std::map<int, gpu::FetchTrace> traces;  // plan draw -> trace, for the draws the prepared plan kept
  trace_draws(runner, plan, draws, windows, view, radius, traces, image);
  // Draws whose reads overflowed their slots (a dynamic loop, the blurs' run-time radius), again with more.
  for (;;) {
    draws.clear();
    for (const auto& [i, t] : traces)
      if (t.overflowed_pixels > 0 && windows[i].max_taps < kMaxTraceTaps) {
        windows[i].max_taps = std::min(2 * windows[i].max_taps, kMaxTraceTaps);
        draws.push_back(i);
      }
    if (draws.empty()) break;
    trace_draws(runner, plan, draws, windows, view, radius, traces, nullptr);
  }
  std::vector<gpu::FetchTrace> out;
  std::map<std::string, int> draws_in_pass;
  for (auto& [i, t] : traces) {
    t.draw = draws_in_pass[t.pass]++;
    t.plan_draw = i;
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace aovar::trace
