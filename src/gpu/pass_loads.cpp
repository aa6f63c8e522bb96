#include "gpu/pass_loads.h"

#include <map>

#include "analyze/analyze.h"

namespace aovar::gpu {
namespace {

// Share of the full-resolution output a draw shades: AO-resolution draws resolution², MIP level l 1/4^l.
double draw_share(const render::PipelinePlan& plan, const render::Draw& d) {
  double share = d.full_resolution ? 1.0 : plan.resolution * plan.resolution;
  for (int l = 0; l < d.level; ++l) share /= 4.0;
  return share;
}

double written_bytes(const render::PipelinePlan& plan, const render::Draw& d) {
  double bytes = 0;
  for (const render::TextureRef& out : d.outputs)
    if (out.texture >= 0) bytes += render::format_bytes(plan.textures[out.texture].format);
  return bytes;
}

std::string axis(const render::PipelinePlan& plan, const char* name) {
  auto it = plan.axes.find(name);
  return it == plan.axes.end() ? "" : it->second;
}

}  // namespace

std::vector<PassLoad> pass_loads(const render::PipelinePlan& plan, std::map<std::string, analyze::ProgramCost>& analysed) {
  const auto texel_bytes = analyze::binding_bytes(axis(plan, "depth_format"), axis(plan, "normals"));
  std::vector<PassLoad> loads;
  for (const std::string& pass : plan.passes()) {
    PassLoad load{pass, 0, 0, 0, 0};
    double share_sum = 0;
    for (const render::Draw& d : plan.draws) {
      if (d.pass != pass) continue;
      const render::Shader& fragment = plan.shaders[d.fragment];
      auto it = analysed.find(fragment.program_key);
      if (it == analysed.end()) it = analysed.emplace(fragment.program_key, analyze::analyze_spirv(fragment.spirv)).first;
      const double share = draw_share(plan, d);
      load.draws += 1;
      share_sum += share;
      // Per shaded pixel, weighted by how many pixels each draw shades (the pyramid's levels differ).
      load.fetches += share * it->second.total_fetches();
      load.bytes_per_pixel += share * (analyze::bytes_per_pixel(it->second.fetches, texel_bytes) + written_bytes(plan, d));
    }
    if (load.draws == 0) continue;
    load.pixel_share = share_sum / load.draws;
    if (share_sum > 0) load.fetches /= share_sum, load.bytes_per_pixel /= share_sum;
    loads.push_back(load);
  }
  return loads;
}

}  // namespace aovar::gpu
