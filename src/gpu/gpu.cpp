#include "gpu/gpu.h"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gpu/families.h"
#include "gpu/family_specs.h"
#include "gpu/gl/analysis.h"
#include "gpu/null_device.h"
#include "gpu/spirv_unroll.h"
#include "render/plan.h"
#include "render/vulkan/vk_pipeline.h"
#include "util/clock.h"
#include "util/isolated.h"
#include "util/parallel.h"

namespace aovar::gpu {
namespace {

struct Program {
  std::vector<std::uint32_t> shipped, unrolled;
  int loops_unrolled = 0;
};

// A pipeline shared by every variant that draws the same programs into the same formats: compiled once.
struct UniquePipeline {
  PipelineShape shipped, unrolled;
  int loops_unrolled = 0;
  std::string vertex_key, fragment_key;
};

struct PassRef {
  std::string pass;
  int pipeline = -1;
};

// The work, made in the parent before any fork (children inherit it): distinct pipelines, and per variant
// its passes pointing at them.
struct Work {
  std::map<std::string, Program> programs;  // by key; map nodes stay put, so shapes may point into them
  std::vector<UniquePipeline> pipelines;
  std::map<std::string, int> by_signature;
  std::vector<std::pair<std::string, std::vector<PassRef>>> variants;
};

const Program& program(Work& w, const render::Shader& shader) {
  auto [it, fresh] = w.programs.try_emplace(shader.program_key);
  if (fresh) {
    UnrollRewrite r = with_unroll_hints(shader.spirv);
    it->second = {shader.spirv, std::move(r.words), r.loops_changed};
  }
  return it->second;
}

int pipeline_of(Work& w, const render::PipelinePlan& plan, const render::Draw& draw) {
  const Program& vs = program(w, plan.shaders[draw.vertex]);
  const Program& fs = program(w, plan.shaders[draw.fragment]);
  std::vector<VkFormat> formats;
  std::string signature = plan.shaders[draw.vertex].program_key + "|" + plan.shaders[draw.fragment].program_key;
  for (const render::TextureRef& out : draw.outputs) {
    formats.push_back(out.texture >= 0 ? render::vk::format_of(plan.textures[out.texture].format) : VK_FORMAT_UNDEFINED);
    signature += fmt::format("|{}", static_cast<int>(formats.back()));
  }
  signature += fmt::format("|{}|{}", static_cast<int>(draw.depth), draw.geometry);
  auto [it, fresh] = w.by_signature.try_emplace(signature, static_cast<int>(w.pipelines.size()));
  if (fresh) {
    UniquePipeline p;
    p.shipped = {&vs.shipped, &fs.shipped, formats, draw.depth, draw.geometry};
    p.unrolled = {&vs.unrolled, &fs.unrolled, formats, draw.depth, draw.geometry};
    p.loops_unrolled = fs.loops_unrolled;
    p.vertex_key = plan.shaders[draw.vertex].program_key;
    p.fragment_key = plan.shaders[draw.fragment].program_key;
    w.pipelines.push_back(std::move(p));
  }
  return it->second;
}

Work plan_work(const compile::CompiledSpace& compiled, const std::vector<int>& variants) {
  Work w;
  for (int v : variants) {
    const render::PipelinePlan plan = render::plan_pipeline(compiled, v, variants::Target::vulkan);
    std::vector<PassRef> passes;
    for (const render::Draw& draw : plan.draws) {
      bool seen = false;
      for (const PassRef& p : passes) seen = seen || p.pass == draw.pass;
      if (seen) continue;  // the separable blur's second draw, SAO's pyramid levels: the same pipeline
      passes.push_back({draw.pass, pipeline_of(w, plan, draw)});
    }
    w.variants.emplace_back(plan.variant, std::move(passes));
  }
  return w;
}

// The child's side, for pipelines slice, slice + slices, ...: "d {device, driver}", then "p <pipeline> {u, s}"
// per pipeline; an exception is "e <what>".
int compile_family(const Work& w, const std::string& family, const std::filesystem::path& icd, std::size_t slice,
                   std::size_t slices, util::LineWriter& out) {
  try {
    NullDevice device(family, icd);
    out.line("d " + nlohmann::json{{"device", device.device_name()}, {"driver", device.driver()}}.dump());
    // Test hook: a compiler crash in this family must cost this family only (tests/gpu/test_gpu.cpp).
    if (const char* crash = std::getenv("AOVAR_GPU_TEST_CRASH"); crash && family == crash) std::raise(SIGSEGV);
    for (std::size_t i = slice; i < w.pipelines.size(); i += slices) {
      const UniquePipeline& p = w.pipelines[i];
      const ShaderStats unrolled = device.fragment_stats(p.unrolled);
      const ShaderStats shipped = p.loops_unrolled ? device.fragment_stats(p.shipped) : unrolled;
      out.line(fmt::format("p {} {}", i, nlohmann::json{{"u", to_json(unrolled)}, {"s", to_json(shipped)}}.dump()));
    }
    return 0;
  } catch (const std::exception& e) {
    out.line(std::string("e ") + e.what());
    return 2;
  }
}

std::string ending(const util::ChildOutcome& how, const std::string& error, std::size_t done, std::size_t total) {
  if (!error.empty()) return error;
  if (how.signal != 0)
    return fmt::format("the RADV compiler crashed (signal {}, {}) after {} of {} pipelines", how.signal,
                       strsignal(how.signal), done, total);
  if (how.cut_off || how.exit_code != 0)
    return fmt::format("the compiling child stopped (exit status {}) after {} of {} pipelines", how.exit_code, done,
                       total);
  return "";
}

// Children per family: ACO compiles one pipeline at a time, so the pipelines are dealt out to a child per core;
// a child's device costs little next to a few dozen pipelines.
std::size_t compiling_children(std::size_t pipelines) {
  constexpr std::size_t kPipelinesPerChild = 32;
  return std::clamp<std::size_t>((pipelines + kPipelinesPerChild - 1) / kPipelinesPerChild, 1, util::pool_threads(0));
}

FamilyStats run_family(const Work& w, const std::string& family, const std::filesystem::path& icd) {
  FamilyStats f;
  f.family = family;
  f.compiler = "radv";
  std::vector<std::optional<std::pair<ShaderStats, ShaderStats>>> results(w.pipelines.size());
  std::size_t done = 0;
  const std::size_t slices = compiling_children(w.pipelines.size());
  std::vector<std::function<int(util::LineWriter&)>> children;
  for (std::size_t k = 0; k < slices; ++k)
    children.push_back([&, k](util::LineWriter& out) { return compile_family(w, family, icd, k, slices, out); });
  std::vector<std::string> errors(slices);
  const auto outcomes = util::run_isolated_all(children, [&](std::size_t child, const std::string& line) {
    if (line.size() < 2) return;
    const std::string rest(line, 2);
    if (line[0] == 'd') {
      const auto j = nlohmann::json::parse(rest);
      f.device = j.at("device").get<std::string>();
      f.driver = j.at("driver").get<std::string>();
    } else if (line[0] == 'p') {
      const std::size_t space = rest.find(' ');
      const auto j = nlohmann::json::parse(rest.substr(space + 1));
      results.at(std::stoul(rest.substr(0, space))) = {stats_from_json(j.at("u")), stats_from_json(j.at("s"))};
      ++done;
    } else if (line[0] == 'e') {
      errors[child] = rest;
    }
  });
  for (std::size_t k = 0; k < slices && f.error.empty(); ++k)
    f.error = ending(outcomes[k], errors[k], done, w.pipelines.size());
  std::vector<int> index(w.pipelines.size(), -1);  // pipeline -> its place in f.pipelines (done ones only)
  for (std::size_t i = 0; i < w.pipelines.size(); ++i) {
    if (!results[i]) continue;
    const UniquePipeline& p = w.pipelines[i];
    index[i] = static_cast<int>(f.pipelines.size());
    f.pipelines.push_back(std::make_shared<const PipelineStats>(PipelineStats{
        p.vertex_key, p.fragment_key, p.loops_unrolled, 0, results[i]->first, results[i]->second, {}}));
  }
  for (const auto& [key, refs] : w.variants) {
    VariantStats v{key, {}};
    bool complete = true;
    for (const PassRef& r : refs) {
      if (index[r.pipeline] < 0) complete = false;
      else v.passes.push_back({r.pass, index[r.pipeline], f.pipelines[index[r.pipeline]]});
    }
    if (complete) f.variants.push_back(std::move(v));
  }
  return f;
}

}  // namespace

const PassStats* VariantStats::pass(const std::string& name) const {
  for (const PassStats& p : passes)
    if (p.pass == name) return &p;
  return nullptr;
}

ShaderStats VariantStats::total(bool unrolled) const {
  std::vector<const ShaderStats*> all;
  for (const PassStats& p : passes) all.push_back(unrolled ? &p.unrolled() : &p.shipped());
  return combine(all);
}

GpuAnalysis analyze_gpu(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                        const GpuOptions& options) {
  const auto start = util::Clock::now();
  if (options.families.empty()) throw std::runtime_error("gpu: no family given (write e.g. --gpu navi21)");
  std::vector<std::string> amd, gl;
  for (const std::string& name : options.families) (gl_chip(name) ? gl : amd).push_back(name);
  std::filesystem::path icd = options.icd;
  if (!amd.empty()) {
    if (icd.empty()) icd = find_radeon_icd();
    try {
      check_families(icd, amd);
    } catch (const std::runtime_error& e) {  // the name may have meant a GL chip
      std::string chips;
      for (const FamilySpec* c : gl_chips()) chips += (chips.empty() ? "" : ", ") + c->family;
      throw std::runtime_error(fmt::format("{}; GL chips: {}", e.what(), chips));
    }
  }
  GlChipsAnalysis gl_stats;
  if (!gl.empty())  // checks first
    gl_stats = analyze_gl_chips(compiled, variants, gl, options.scope.cache_dir, options.calibration);
  GpuAnalysis a;
  if (!amd.empty()) {
    const Work work = plan_work(compiled, variants);
    a.pipelines = static_cast<int>(work.pipelines.size());
    for (const std::string& family : amd) a.families.push_back(run_family(work, family, icd));
  }
  // In the order asked.
  std::vector<FamilyStats> ordered;
  for (const std::string& name : options.families) {
    std::vector<FamilyStats>& from = gl_chip(name) ? gl_stats.chips : a.families;
    for (FamilyStats& f : from)
      if (f.family == name && !f.family.empty()) ordered.push_back(std::move(f)), f.family.clear();
  }
  a.families = std::move(ordered);
  a.gl_programs = gl_stats.programs;
  a.seconds = util::seconds_since(start);
  return a;
}

}  // namespace aovar::gpu
