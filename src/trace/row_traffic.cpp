#include "trace/row_traffic.h"

#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "compile/generate.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"

namespace aovar::trace {

TrafficStats add_row_traffic(const std::vector<table::CostRow*>& rows, const RowGpuRequest& request) {
  TrafficStats total;
  std::set<std::string> keys;
  std::map<std::pair<std::string, std::string>, std::vector<table::CostRow*>> by_view;  // (scene, view) -> rows
  for (table::CostRow* r : rows)
    if (!r->gpu.empty()) {
      keys.insert(r->variant);
      by_view[{r->scene, r->view}].push_back(r);
    }
  if (keys.empty()) return total;

  compile::CompileOptions co{request.scope};
  co.scope.targets = {variants::Target::vulkan};
  co.globs.assign(keys.begin(), keys.end());
  const compile::CompiledSpace compiled = compile::compile_space(co);
  if (!compiled.ok())
    throw std::runtime_error("trace: the rows' variants do not compile: " + compiled.diagnostics.front());
  std::map<std::string, int> index;
  for (std::size_t i = 0; i < compiled.space.variants.size(); ++i) index[compiled.space.variants[i].key] = int(i);
  std::vector<int> all;
  for (const auto& [key, i] : index) all.push_back(i);
  const auto loads = gpu::variant_loads(compiled, all);

  runner::RunnerOptions ro;
  ro.backend = render::backend_for(variants::Target::vulkan);  // trace builds run on the Vulkan target
  const gpu::Frame frame = request.gpu.frame;
  ro.size = frame;
  ro.calibration = request.calibration;
  ro.device.threads = request.scope.threads;
  runner::VariantRunner runner(compiled, ro);
  TraceOptions options;
  options.window_share = request.gpu.window;
  for (auto& [where, view_rows] : by_view) {
    scene::LoadOptions lo;
    lo.views_file = request.views_file;
    const scene::Scene scene = scene::load_scene(where.first, lo);
    const scene::View& view = scene.view(where.second);
    runner.use_scene(scene);
    std::vector<int> variants;
    std::map<std::string, table::GpuCosts> costs;
    for (const table::CostRow* r : view_rows)
      if (auto it = index.find(r->variant); it != index.end() && costs.emplace(r->variant, r->gpu).second)
        variants.push_back(it->second);
    const float radius = request.radius > 0 ? request.radius : scene.ao_radius;
    const TrafficCache cache(request.scope.cache_dir, view_context(scene, view, radius, frame, options));
    const TrafficStats s = add_traffic(runner, variants, view, radius, loads, frame, costs, options, cache);
    for (table::CostRow* r : view_rows)
      if (auto it = costs.find(r->variant); it != costs.end()) r->gpu = it->second;
    total += s;
  }
  return total;
}

}  // namespace aovar::trace

namespace aovar::trace {

RowGpuResult add_gpu_costs(const std::vector<table::CostRow*>& rows, const RowGpuRequest& request,
                           const std::function<void(const std::string&)>& say) {
  RowGpuResult out;
  std::set<std::string> keys;
  for (const table::CostRow* r : rows) keys.insert(r->variant);
  const GpuEstimateOptions& gpu = request.gpu;
  say(fmt::format("analysing {} variants on RADV's null device ({})", keys.size(), fmt::join(gpu.families, ", ")));
  gpu::KeyedCosts costs = gpu::costs_by_key({request.scope, gpu.families, gpu.frame, request.calibration}, keys);
  for (table::CostRow* r : rows)
    if (auto it = costs.by_variant.find(r->variant); it != costs.by_variant.end()) r->gpu = it->second;
  for (const auto& e : costs.errors) say("note: --gpu " + e);
  out.errors = std::move(costs.errors);
  out.mesa = costs.mesa;
  out.pipelines = costs.pipelines;
  out.seconds = costs.seconds;
  if (gpu.trace) {
    say(fmt::format("tracing {} variants' texel fetches on their views at {}x{} ({}) through each family's caches",
                    keys.size(), gpu.frame.width, gpu.frame.height, render::backend_for(variants::Target::vulkan)));
    out.traffic = add_row_traffic(rows, request);
  }
  out.families = gpu.families;
  out.frame = fmt::format("{}x{}", gpu.frame.width, gpu.frame.height);
  out.traced = gpu.trace;
  out.window_share = gpu.window;
  return out;
}

nlohmann::json RowGpuResult::to_json() const {
  nlohmann::json j = {{"families", families}, {"frame", frame}, {"mesa", mesa}, {"pipelines", pipelines},
                      {"seconds", seconds}, {"errors", errors}};
  j["trace"] = traced ? nlohmann::json{{"window_share", window_share}, {"traced_draws", traffic.traced_draws},
                                       {"shared_draws", traffic.shared_draws}, {"simulations", traffic.simulations}, {"cached_draws", traffic.cached_draws},
                                       {"trace_seconds", traffic.trace_seconds},
                                       {"simulate_seconds", traffic.simulate_seconds}}
                      : nlohmann::json(nullptr);
  return j;
}

}  // namespace aovar::trace
