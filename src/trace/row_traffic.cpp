#include "trace/row_traffic.h"

#include <algorithm>
#include <set>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "compile/generate.h"
#include "gpu/costs.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"

namespace aovar::trace {

// The rows' variants compiled for the Vulkan target (trace builds run there), with their index. A variant's pass
// loads are analysed when a row of it is first estimated, not for every variant compiled: most of a screen's
// candidates are dropped before either.
struct RowTracer::Compiled {
  compile::CompiledSpace compiled;
  std::map<std::string, int> index;
  std::map<std::string, std::vector<gpu::PassLoad>> loads;  // by variant key, those analysed so far
  std::map<std::string, analyze::ProgramCost> analysed;     // by program key (gpu::pass_loads)

  // The loads of every variant of `keys` that this compilation holds, analysed now where they are not yet.
  void analyse(const std::set<std::string>& keys) {
    std::vector<int> missing;
    for (const std::string& key : keys)
      if (auto it = index.find(key); it != index.end() && !loads.count(key)) missing.push_back(it->second);
    loads.merge(gpu::variant_loads(compiled, missing, &analysed));
  }
};

namespace {

using CompiledRows = RowTracer::Compiled;

CompiledRows compile_rows(const std::set<std::string>& keys, const compile::RunScope& scope) {
  compile::CompileOptions co{scope};
  co.scope.targets = {variants::Target::vulkan};
  co.globs.assign(keys.begin(), keys.end());
  CompiledRows out{compile::compile_space(co), {}, {}, {}};
  if (!out.compiled.ok())
    throw std::runtime_error("trace: the rows' variants do not compile: " + out.compiled.diagnostics.front());
  for (std::size_t i = 0; i < out.compiled.space.variants.size(); ++i)
    out.index[out.compiled.space.variants[i].key] = int(i);
  return out;
}

std::set<std::string> keys_with_costs(const std::vector<table::CostRow*>& rows) {
  std::set<std::string> keys;
  for (const table::CostRow* r : rows)
    if (!r->gpu.empty()) keys.insert(r->variant);
  return keys;
}

}  // namespace

// One scene view: the scene loaded once, its traffic cache and the traffic simulated on it so far.
struct RowTracer::View {
  const scene::Scene& scene;
  std::string name;
  float radius = 0;
  TrafficCache cache;
  TrafficMemo memo;
  const scene::View& view() const { return scene.view(name); }
};

RowTracer::RowTracer(RowGpuRequest request) : request_(std::move(request)) {}
RowTracer::~RowTracer() = default;

void RowTracer::expect(const std::set<std::string>& keys) { expected_.insert(keys.begin(), keys.end()); }

RowTracer::Compiled& RowTracer::compiled_for(const std::set<std::string>& keys) {
  if (!compiled_ || !std::includes(compiled_keys_.begin(), compiled_keys_.end(), keys.begin(), keys.end())) {
    std::set<std::string> all = expected_;
    all.insert(keys.begin(), keys.end());
    runner_.reset();  // it renders the compilation it was made with
    compiled_ = std::make_unique<Compiled>(compile_rows(all, request_.scope));
    compiled_keys_ = std::move(all);
  }
  compiled_->analyse(keys);
  return *compiled_;
}

runner::VariantRunner& RowTracer::runner() {
  if (!runner_) {
    runner::RunnerOptions ro;
    ro.backend = render::backend_for(variants::Target::vulkan);  // trace builds run on the Vulkan target
    ro.size = request_.gpu.frame;
    ro.calibration = request_.calibration;
    ro.device.threads = request_.scope.threads;
    runner_ = std::make_unique<runner::VariantRunner>(compiled_->compiled, ro);
  }
  return *runner_;
}

RowTracer::View& RowTracer::view_of(const table::CostRow& row) {
  auto& slot = views_[{row.scene, row.view}];
  if (!slot) {
    auto& loaded = scenes_[row.scene];
    if (!loaded) {
      scene::LoadOptions lo;
      lo.views_file = request_.views_file;
      loaded = std::make_unique<scene::Scene>(scene::load_scene(row.scene, lo));
    }
    const scene::Scene& scene = *loaded;
    const float radius = request_.radius > 0 ? request_.radius : scene.ao_radius;
    TraceOptions options;
    options.window_share = request_.gpu.window;
    std::string context = view_context(scene, scene.view(row.view), radius, request_.gpu.frame, options);
    slot.reset(new View{scene, row.view, radius, TrafficCache(request_.scope.cache_dir, std::move(context)), {}});
  }
  return *slot;
}

TrafficStats RowTracer::trace(const std::vector<table::CostRow*>& rows) {
  TrafficStats total = std::exchange(read_ahead_, {});
  const std::set<std::string> keys = keys_with_costs(rows);
  if (keys.empty()) return total;
  const Compiled& c = compiled_for(keys);
  std::map<std::pair<std::string, std::string>, std::vector<table::CostRow*>> by_view;  // (scene, view) -> rows
  for (table::CostRow* r : rows)
    if (!r->gpu.empty()) by_view[{r->scene, r->view}].push_back(r);

  runner::VariantRunner& runner = this->runner();
  TraceOptions options;
  options.window_share = request_.gpu.window;
  for (auto& [where, view_rows] : by_view) {
    View& v = view_of(*view_rows.front());
    runner.use_scene(v.scene);
    std::vector<int> variants;
    std::map<std::string, table::GpuCosts> costs;
    for (const table::CostRow* r : view_rows)
      if (auto it = c.index.find(r->variant); it != c.index.end() && costs.emplace(r->variant, r->gpu).second)
        variants.push_back(it->second);
    total += add_traffic(runner, variants, v.view(), v.radius, c.loads, request_.gpu.frame, costs, options, v.cache,
                         &v.memo);
    for (table::CostRow* r : view_rows)
      if (auto it = costs.find(r->variant); it != costs.end()) r->gpu = it->second;
  }
  return total;
}

std::vector<std::map<std::string, double>> RowTracer::cached(const std::vector<table::CostRow*>& rows,
                                                             const std::string& family) {
  std::vector<std::map<std::string, double>> out(rows.size());
  const std::set<std::string> keys = keys_with_costs(rows);
  if (keys.empty()) return out;
  const Compiled& c = compiled_for(keys);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const table::CostRow& r = *rows[i];
    auto index = c.index.find(r.variant);
    auto cost = r.gpu.find(family);
    if (index == c.index.end() || cost == r.gpu.end()) continue;
    View& v = view_of(r);
    const render::PipelinePlan plan =
        runner::plan_variant(c.compiled, index->second, variants::Target::vulkan, request_.calibration);
    out[i] = cached_pass_estimates(cost->second, TraceSet::draws_of(plan), c.loads.at(r.variant), family,
                                   request_.gpu.frame, v.cache, v.memo, read_ahead_);
  }
  return out;
}

TrafficStats add_row_traffic(const std::vector<table::CostRow*>& rows, const RowGpuRequest& request) {
  return RowTracer(request).trace(rows);
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
