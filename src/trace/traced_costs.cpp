#include "trace/traced_costs.h"

#include <chrono>
#include <cmath>
#include <utility>

#include "gpu/cache_estimate.h"
#include "gpu/family_specs.h"

namespace aovar::trace {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

const gpu::PassLoad* load_of(const std::vector<gpu::PassLoad>& loads, const std::string& pass) {
  for (const gpu::PassLoad& l : loads)
    if (l.pass == pass) return &l;
  return nullptr;
}

}  // namespace

TrafficStats add_traffic(runner::VariantRunner& runner, const std::vector<int>& variants, const scene::View& view,
                         float radius, const std::map<std::string, std::vector<gpu::PassLoad>>& loads,
                         gpu::Frame frame, std::map<std::string, table::GpuCosts>& costs,
                         const TraceOptions& options) {
  TrafficStats stats;
  TraceSet set(runner, view, radius, options);
  std::map<std::pair<const gpu::FetchTrace*, std::string>, gpu::CacheSimResult> simulated;
  for (int v : variants) {
    const std::string& key = runner.compiled().space.variants.at(v).key;
    auto row = costs.find(key);
    auto variant_loads = loads.find(key);
    if (row == costs.end() || variant_loads == loads.end()) continue;
    auto t0 = std::chrono::steady_clock::now();
    const std::vector<const gpu::FetchTrace*> traces = set.of(v);
    stats.trace_seconds += seconds_since(t0);
    for (auto& [family, cost] : row->second) {
      const gpu::FamilySpec* spec = gpu::family_spec(family);
      if (!spec || spec->caches.empty()) continue;
      const gpu::CacheHierarchy hierarchy = gpu::hierarchy_of(*spec);
      // The draws of each pass, simulated (once per trace and family) and merged.
      std::map<std::string, std::vector<gpu::CacheSimResult>> by_pass;
      auto t1 = std::chrono::steady_clock::now();
      for (const gpu::FetchTrace* t : traces) {
        auto [it, fresh] = simulated.try_emplace({t, family});
        if (fresh) {
          it->second = gpu::simulate(*t, hierarchy);
          ++stats.simulations;
        }
        by_pass[t->pass].push_back(it->second);
      }
      stats.simulate_seconds += seconds_since(t1);
      double total = 0;
      for (table::GpuPassCost& pass : cost.passes) {
        auto sims = by_pass.find(pass.pass);
        const gpu::PassLoad* load = load_of(variant_loads->second, pass.pass);
        if (sims != by_pass.end() && load) gpu::apply_cache_model(pass, *load, *spec, frame, gpu::merge(sims->second));
        total += pass.est_ms;
      }
      cost.est_ms = total;
      cost.view = view.name;
    }
  }
  stats.traced_draws = set.traced_draws();
  stats.shared_draws = set.shared_draws();
  return stats;
}

}  // namespace aovar::trace
