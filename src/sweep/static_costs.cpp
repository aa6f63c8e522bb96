#include "sweep/static_costs.h"

#include <algorithm>
#include <stdexcept>

#include "analyze/analyze.h"
#include "compile/generate.h"
#include "render/backend.h"
#include "util/hash.h"

namespace aovar::sweep {
namespace {

// Rows of a backend that runs the Vulkan target carry its SPIR-V programs' hash; an unregistered name (a
// hand-written table's) carries none.
bool runs_spirv(const std::string& backend) {
  const auto names = render::backend_names();
  return std::find(names.begin(), names.end(), backend) != names.end() &&
         render::target_of(backend) == variants::Target::vulkan;
}

// One program's counts as the table's type.
table::ProgramCounts program_counts(const analyze::ProgramCost& c) {
  table::ProgramCounts k;
  k.fetches = {c.fetch(analyze::kDepth), c.fetch(analyze::kNormal), c.fetch(analyze::kPosition),
               c.fetch(analyze::kInput), c.fetch(analyze::kHistory), c.fetch(analyze::kPrefilter)};
  k.alu = c.alu;
  k.fma = c.fma;
  k.div = c.div;
  k.transcendental = c.transcendental;
  k.cmp_select = c.cmp_select;
  k.branches = c.branches;
  k.unprojections = c.unprojections;
  k.projections = c.projections;
  for (const auto& l : c.loops) ++(l.constant ? k.constant_loops : k.dynamic_loops);
  return k;
}

// Per instruction class, weighted like `work`: the AO pass apart from the others, because its reads scatter
// over the radius while the blurs' and the upsample's read neighbours.
table::ClassCounts class_counts(const analyze::ProgramCost& k) {
  return {k.total_fetches(), k.fetch(analyze::kPrefilter), k.alu, k.transcendental + k.normalize_length, k.div,
          k.cmp_select, k.branches};
}

}  // namespace

table::CostRow unmeasured_row(const table::CostRow& like, const std::string& key, const VariantStatic& vs) {
  table::CostRow r;
  r.variant = key;
  r.axes = vs.axes;
  r.scene = like.scene;
  r.view = like.view;
  r.backend = like.backend;
  r.size = like.size;
  r.threads = like.threads;
  r.spirv_hash = runs_spirv(r.backend) ? vs.vulkan_programs : std::string();
  r.static_cost = vs.cost;
  return r;
}

std::map<std::string, VariantStatic> static_costs(const measure::MeasureOptions& mo, const std::vector<std::string>& globs,
                                                  const std::set<std::string>& exclude) {
  compile::CompileOptions co{mo.scope};
  co.scope.targets = {variants::Target::vulkan};
  co.globs = globs;
  co.exclude = exclude;
  auto c = compile::compile_space(co);
  std::map<std::string, VariantStatic> out;
  // measure compiled the same programs already (from the cache): a failure here is not a template error.
  if (!c.ok()) throw std::runtime_error("sweep: static analysis: " + (c.diagnostics.empty() ? std::string("compile failed") : c.diagnostics.front()));
  const int t = c.target_index(variants::Target::vulkan);
  std::map<int, analyze::ProgramCost> by_program;
  auto cost = [&](int program) -> const analyze::ProgramCost& {
    auto it = by_program.find(program);
    if (it == by_program.end()) it = by_program.emplace(program, analyze::analyze_spirv(c.builds[t][program].output.spirv)).first;
    return it->second;
  };
  for (const auto& entry : c.space.variants) {
    VariantStatic vs;
    std::string depth_format, normals, blur;
    double resolution = 1.0;
    for (int a = 0; a < variants::kAxisCount; ++a) {
      int i = entry.point[a] >= 0 ? entry.point[a] : 0;
      auto axis = variants::axis_at(a);
      const std::string& v = c.manifest.value(axis, i).text;
      vs.axes[std::string(variants::axis_info(axis).name)] = v;
      if (axis == variants::Axis::depth_format) depth_format = v;
      if (axis == variants::Axis::normals) normals = v;
      if (axis == variants::Axis::blur) blur = v;
      if (axis == variants::Axis::resolution) resolution = std::stod(v);
    }
    util::Hasher programs;  // as measure's spirv_hash: every program of every pass, in pass order
    for (const auto& pass : entry.passes)
      for (int p : pass)
        if (p >= 0) programs.add(c.builds[t][p].hash);
    vs.vulkan_programs = programs.hex();
    int v = static_cast<int>(&entry - c.space.variants.data());
    vs.same_as = c.space.variants[c.variant_same_as[v] >= 0 ? c.variant_same_as[v] : v].key;
    // Work per output pixel of the fullscreen passes (src/render/plan.h): each program's ALU + texture reads,
    // times its draws (separable passes 2, the z pyramid 1 + 1/4 + ... < 4/3) and the share of output
    // pixels it covers (AO-resolution passes resolution², the upsample 1). The G-buffer is left out: it
    // depends on the geometry, not the variant.
    analyze::ProgramCost ao, total, ao_weighted, others_weighted;
    double work = 0;
    for (std::size_t p = 0; p < c.manifest.passes.size(); ++p) {
      int fragment = entry.passes[p][1];
      if (fragment < 0) continue;
      const std::string& pass = c.manifest.passes[p].name;
      const auto& pc = cost(fragment);
      total += pc;
      if (pass == "ao") ao = pc;
      if (pass == "gbuffer") continue;
      // Prefilter passes of more than one draw (render/plan.cpp's prefilter(): a pyramid's levels, the depth
      // Gaussian's two 1-D draws), named as the renderer names them.
      double draws = (pass == "zmip" || pass == "depth_mip") ? 4.0 / 3.0 : (pass == "unsharp_blur" || (pass.rfind("blur", 0) == 0 && blur == "separable")) ? 2.0 : 1.0;
      double pixels = pass == "upsample" ? 1.0 : resolution * resolution;
      work += draws * pixels * (pc.alu + pc.total_fetches());
      (pass == "ao" ? ao_weighted : others_weighted) += pc.scaled(draws * pixels);
    }
    vs.cost.ao = program_counts(ao);
    vs.cost.passes = program_counts(total);
    vs.cost.ao_bytes_per_pixel = analyze::bytes_per_pixel(ao.fetches, analyze::binding_bytes(depth_format, normals));
    vs.cost.work_per_pixel = work;
    vs.cost.weighted_ao = class_counts(ao_weighted);
    vs.cost.weighted_others = class_counts(others_weighted);
    out[entry.key] = std::move(vs);
  }
  return out;
}

}  // namespace aovar::sweep
