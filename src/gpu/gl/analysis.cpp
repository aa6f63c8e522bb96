#include "gpu/gl/analysis.h"

#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "compile/glslang_compiler.h"
#include "compile/parameters.h"
#include "gpu/family_specs.h"
#include "gpu/gl/compiler.h"
#include "gpu/gl/unroll.h"
#include "render/plan.h"
#include "util/hash.h"
#include "util/parallel.h"
#include "util/verified_cache.h"

namespace aovar::gpu {
namespace fs = std::filesystem;
namespace {

// Bumped when the runner's protocol or what the sources are made from changes: old entries stop matching.
constexpr const char* kGlStatsVersion = "gl-stats 2";  // 2: blur loops unrolled at the radius (issue 56)

struct Pair {
  std::string vertex_key, fragment_key;
  GlProgram program;  // unrolled sources
  int loops_unrolled = 0, loops_kept = 0;
  GlslInputs specialised;  // the parameter values the fragment's unrolled loop bounds read
};

struct Plan {
  std::vector<Pair> pairs;
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, int>>>> variants;  // key, (pass, pair)
};

GlslUnroll unrolled(const render::Shader& shader, const GlslInputs& inputs) {
  if (shader.glsl.empty()) throw std::runtime_error("gl chips: " + shader.program_key + " has no gles30 source");
  return unroll_loops(compile::preprocess_es(shader.glsl, shader.stage), inputs);
}

// "params.radius_px=3;..." (empty for none): a GlslInputs as part of a key.
std::string inputs_text(const GlslInputs& inputs) {
  std::string out;
  for (const auto& [name, value] : inputs) out += fmt::format("{}={};", name, value);
  return out;
}

// The values each program's parameters render with, by program key, as its source reads them ("params.<name>",
// shader_src/README.md): the calibrated value of "<pass>.<name>" where `calibration` has one for the variant,
// else the manifest's; rounded to float, as the AOParams block uploads them. By program, not by the draw's
// timing group: SAO's keyed blur times as "blur" but takes the parameters of the manifest pass blur_keyed.
std::map<std::string, GlslInputs> program_inputs(const compile::CompiledSpace& compiled, int variant,
                                                 const variants::CalibratedValues& calibration) {
  std::map<std::string, GlslInputs> by_pass;
  for (const compile::VariantParam& p : compile::variant_params(compiled, variant, calibration)) {
    const std::size_t dot = p.key.find('.');
    by_pass[p.key.substr(0, dot)]["params." + p.key.substr(dot + 1)] = static_cast<float>(p.value);
  }
  std::map<std::string, GlslInputs> by_program;
  const auto& entry = compiled.space.variants.at(variant);
  for (std::size_t i = 0; i < compiled.manifest.passes.size(); ++i)
    for (int program : entry.passes[i])
      if (program >= 0) by_program[compiled.space.programs[program].key] = by_pass[compiled.manifest.passes[i].name];
  return by_program;
}

// One program to unroll: a shader at its pass's parameter values (a vertex shader at none: no loop of its
// reads a parameter).
struct UnrollJob {
  const render::Shader* shader = nullptr;
  GlslInputs inputs;
  GlslUnroll result;
};

struct PassUse {
  std::string pass;
  std::size_t vertex = 0, fragment = 0;  // indices into the jobs
};
using VariantUses = std::pair<std::string, std::vector<PassUse>>;  // a variant's key and its passes

// The distinct pairs of the unrolled programs: two passes share one when their programs are the same and so
// are the values their fragment's loop bounds read.
Plan pairs_of(const std::vector<UnrollJob>& jobs, const std::vector<VariantUses>& uses) {
  Plan plan;
  std::map<std::string, int> by_key;
  for (const auto& [variant, passes] : uses) {
    std::vector<std::pair<std::string, int>> drawn;
    for (const PassUse& u : passes) {
      const UnrollJob &vj = jobs[u.vertex], &fj = jobs[u.fragment];
      const std::string &vk = vj.shader->program_key, &fk = fj.shader->program_key;
      const auto [it, fresh] = by_key.try_emplace(vk + "|" + fk + "|" + inputs_text(fj.result.specialised),
                                                  static_cast<int>(plan.pairs.size()));
      if (fresh)
        plan.pairs.push_back({vk, fk, {fk, vj.result.source, fj.result.source}, fj.result.unrolled, fj.result.kept,
                              fj.result.specialised});
      drawn.emplace_back(u.pass, it->second);
    }
    plan.variants.emplace_back(variant, std::move(drawn));
  }
  return plan;
}

// Each variant's passes (each pass once: the separable blur's second draw is the same program) and the
// distinct program pairs they draw. A pair is its two programs and the parameter values its loop bounds read
// (a blur at radius 1 and at 3 are two pairs; at another depth_sigma, the same one). Each program is unrolled
// once per distinct parameter values, on every core.
Plan plan_pairs(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                const variants::CalibratedValues& calibration) {
  std::map<std::string, render::Shader> shaders;  // program key -> the program (first seen)
  std::map<std::string, std::size_t> job_of;      // program key | inputs -> index into jobs
  std::vector<UnrollJob> jobs;
  std::vector<VariantUses> uses;
  const auto job = [&](const render::Shader& shader, const GlslInputs& inputs) {
    const render::Shader& kept = shaders.try_emplace(shader.program_key, shader).first->second;
    const auto [it, fresh] = job_of.try_emplace(shader.program_key + "|" + inputs_text(inputs), jobs.size());
    if (fresh) jobs.push_back({&kept, inputs, {}});
    return it->second;
  };
  for (int v : variants) {
    const render::PipelinePlan p = render::plan_pipeline(compiled, v, variants::Target::gles30);
    const std::map<std::string, GlslInputs> inputs = program_inputs(compiled, v, calibration);
    std::vector<PassUse> passes;
    for (const render::Draw& draw : p.draws) {
      bool seen = false;
      for (const PassUse& u : passes) seen = seen || u.pass == draw.pass;
      if (seen) continue;
      const render::Shader& fragment = p.shaders[draw.fragment];
      const auto in = inputs.find(fragment.program_key);
      passes.push_back({draw.pass, job(p.shaders[draw.vertex], {}),
                        job(fragment, in == inputs.end() ? GlslInputs{} : in->second)});
    }
    uses.emplace_back(p.variant, std::move(passes));
  }
  util::run_parallel(jobs.size(), 0,
                     [&](std::size_t i) { jobs[i].result = unrolled(*jobs[i].shader, jobs[i].inputs); });
  return pairs_of(jobs, uses);
}

struct Cached {
  std::string renderer, version;
  ShaderStats stats;
};

// The cache of GL statistics, on the verified layer (util/verified_cache.h): an entry names its full key and
// carries a checksum of its content. `key` is gl_cache_key's hash of everything the statistics depend on.
std::string gl_entry_key(const std::string& chip, const std::string& key) { return "gl-stats " + chip + " " + key; }

// An entry is used only when the layer verifies it and the vendor's parser reads a fragment line in it;
// anything else is compiled again with one warning, and the entry rewritten.
std::optional<Cached> read_entry(const util::VerifiedCache& cache, const std::string& entry_key, const GlVendor& vendor) {
  const auto text = cache.read(entry_key);
  if (!text) return std::nullopt;
  try {
    const nlohmann::json j = nlohmann::json::parse(*text);
    auto stats = vendor.fragment_stats(j.at("messages").get<std::vector<std::string>>());
    if (!stats) throw std::runtime_error("no statistics line the " + vendor.name + " parser reads");
    return Cached{j.at("renderer").get<std::string>(), j.at("version").get<std::string>(), std::move(*stats)};
  } catch (const std::exception& e) {
    cache.reject(entry_key, e.what());
    return std::nullopt;
  }
}

// A cache that cannot be written never fails the run (the layer warns once): the statistics are right
// without it, the next run compiles again.
void write_entry(const util::VerifiedCache& cache, const std::string& entry_key, const GlBatch& batch,
                 const ShaderStats& stats) {
  const nlohmann::json j = {{"renderer", batch.renderer}, {"version", batch.version},
                            {"messages", std::vector<std::string>{stats.raw}}};
  cache.write(entry_key, j.dump());
}

std::string driver_of(const std::string& gl_version) {  // "OpenGL ES 3.1 Mesa 25.0.7-2~bpo12+1" -> "Mesa 25.0.7-..."
  const std::size_t at = gl_version.find("Mesa");
  return at == std::string::npos ? gl_version : gl_version.substr(at);
}

FamilyStats analyze_chip(const Plan& plan, const FamilySpec& chip, const GlInstall& install,
                         const util::VerifiedCache& cache) {
  const GlVendor& vendor = *gl_vendor(chip.compiler->driver);
  FamilyStats f;
  f.family = chip.family;
  f.compiler = vendor.name;
  std::vector<std::optional<ShaderStats>> stats(plan.pairs.size());
  std::vector<std::string> keys;
  std::vector<GlProgram> todo;
  std::vector<std::size_t> todo_index;
  for (std::size_t i = 0; i < plan.pairs.size(); ++i) {
    const Pair& p = plan.pairs[i];
    keys.push_back(gl_entry_key(chip.family, gl_cache_key(chip.family, chip.compiler->chip, install.mesa,
                                                          p.program.vertex, p.program.fragment, p.specialised)));
    if (auto hit = read_entry(cache, keys.back(), vendor)) {
      f.device = hit->renderer;
      f.driver = driver_of(hit->version);
      stats[i] = std::move(hit->stats);
      ++f.cached;
    } else {
      todo.push_back(p.program);
      todo_index.push_back(i);
    }
  }
  try {
    const GlBatch batch = compile_on_chip(install, vendor, chip.compiler->chip, todo);
    if (!todo.empty()) f.device = batch.renderer, f.driver = driver_of(batch.version);
    for (std::size_t k = 0; k < todo.size(); ++k) {
      const GlResult& r = batch.results[k];
      if (!r.error.empty()) f.program_errors.push_back(r.error);
      if (!r.stats) continue;
      write_entry(cache, keys[todo_index[k]], batch, *r.stats);
      stats[todo_index[k]] = *r.stats;
    }
  } catch (const std::exception& e) {
    f.error = e.what();
  }
  std::vector<int> index(plan.pairs.size(), -1);
  for (std::size_t i = 0; i < plan.pairs.size(); ++i) {
    if (!stats[i]) continue;
    const Pair& p = plan.pairs[i];
    index[i] = static_cast<int>(f.pipelines.size());
    f.pipelines.push_back(std::make_shared<const PipelineStats>(
        PipelineStats{p.vertex_key, p.fragment_key, p.loops_unrolled, p.loops_kept, std::move(*stats[i]), {},
                      p.specialised}));
  }
  for (const auto& [key, passes] : plan.variants) {
    VariantStats v{key, {}};
    bool complete = true;
    for (const auto& [pass, pair] : passes) {
      if (index[pair] < 0) complete = false;
      else v.passes.push_back({pass, index[pair], f.pipelines[index[pair]]});
    }
    if (complete) f.variants.push_back(std::move(v));
  }
  return f;
}

}  // namespace

// The specialised values are in the key by name as well as through the unrolled source they shaped, so that
// two radii never share an entry even where their sources were to coincide.
std::string gl_cache_key(const std::string& chip, const std::string& driver_chip, const std::string& mesa,
                         const std::string& vertex, const std::string& fragment, const GlslInputs& specialised) {
  return util::hash_hex(fmt::format("{}\n{}\n{}\n{}\n{}\n{}\n{}\n{}", kGlStatsVersion, chip, driver_chip, mesa,
                                    inputs_text(specialised), vertex.size(), vertex, fragment));
}

GlChipsAnalysis analyze_gl_chips(const compile::CompiledSpace& compiled, const std::vector<int>& variants,
                                 const std::vector<std::string>& chips, const fs::path& cache_dir,
                                 const variants::CalibratedValues& calibration) {
  const GlInstall install = find_gl_install();
  std::vector<const FamilySpec*> specs;
  for (const std::string& name : chips) {
    const FamilySpec* spec = gl_chip(name);
    if (!spec) throw std::runtime_error(fmt::format("unknown GL chip '{}'", name));
    try {
      check_installed(install, *gl_vendor(spec->compiler->driver));
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("--gpu {}: {}", name, e.what()));
    }
    specs.push_back(spec);
  }
  const Plan plan = plan_pairs(compiled, variants, calibration);
  GlChipsAnalysis a;
  a.programs = static_cast<int>(plan.pairs.size());
  const util::VerifiedCache cache(cache_dir, "gl-stats");
  // One runner process per chip, as many at once as there are cores (each is single-threaded).
  a.chips.resize(specs.size());
  util::run_parallel(specs.size(), 0, [&](std::size_t i) { a.chips[i] = analyze_chip(plan, *specs[i], install, cache); });
  return a;
}

}  // namespace aovar::gpu
