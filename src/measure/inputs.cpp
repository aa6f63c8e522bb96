#include "measure/inputs.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "util/hash.h"

namespace aovar::measure {

std::string plan_text(const render::PipelinePlan& plan,
                      const std::function<std::string(const render::Shader&)>& program) {
  std::string s = fmt::format("res {} prog {} result {}", plan.resolution, plan.progressive, plan.result);
  for (const auto& sh : plan.shaders)
    s += fmt::format("|shader {} {}", program ? program(sh) : sh.program_key, variants::stage_name(sh.stage));
  for (const auto& t : plan.textures)
    s += fmt::format("|tex {} {} {} {} {} {} {}", t.name, render::format_name(t.format), t.full_resolution,
                     t.double_buffered, t.cleared, fmt::join(t.clear, ","), t.levels);
  for (const auto& b : plan.depth_buffers) s += fmt::format("|zbuf {} {}", b.name, b.full_resolution);
  auto ref = [](const render::TextureRef& r) { return fmt::format("{}/{}/{}", r.texture, r.previous, r.level); };
  for (const auto& d : plan.draws) {
    s += fmt::format("|draw {} {} {} {} {} {} {} [{}] depth {} {}", d.name, d.pass, d.geometry, d.vertex, d.fragment,
                     d.full_resolution, d.level, fmt::join(d.params, ","), render::depth_use_name(d.depth),
                     d.depth_buffer);
    for (const auto& [binding, in] : d.inputs) s += fmt::format(" in{}={}", binding, ref(in));
    for (const auto& out : d.outputs) s += " out=" + ref(out);
  }
  return s;
}

VariantInputs variant_inputs(const compile::CompiledSpace& c, int v, int t, const render::PipelinePlan& plan,
                             const std::string& context) {
  util::Hasher programs;
  for (const auto& pass : c.space.variants[v].passes)
    for (int p : pass)
      if (p >= 0) programs.add(c.builds[t][p].hash);
  VariantInputs in;
  in.spirv_hash = programs.hex();
  // The key too: identical variants are measured once per run anyway (duplicates), and a row never
  // stands in for another variant whatever the plan text leaves out.
  util::Hasher all;
  all.add(in.spirv_hash).add(context).add(c.space.variants[v].key).add(plan_text(plan));
  in.inputs_hash = all.hex();
  return in;
}

}  // namespace aovar::measure
