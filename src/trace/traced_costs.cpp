#include "trace/traced_costs.h"

#include <chrono>
#include <cmath>
#include <set>
#include <utility>

#include "gpu/cache_estimate.h"
#include "gpu/family_specs.h"
#include "scene/scene.h"

#include <fmt/format.h>

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

// Whether `memo` holds draw `key` on `family`, reading it from the disk cache into `memo` when it can.
bool known(const std::string& key, const std::string& family, const TrafficCache& cache, TrafficMemo& memo,
           TrafficStats& stats) {
  if (memo.count({key, family})) return true;
  auto hit = cache.find(key, family);
  if (!hit) return false;
  memo[{key, family}] = std::move(*hit);
  ++stats.cached_draws;
  return true;
}

// The estimate of `pass` on `spec` from the traffic of its draws (`sims`), as add_traffic makes it.
void apply_traffic(table::GpuPassCost& pass, const std::vector<gpu::PassLoad>& loads,
                   const std::map<std::string, std::vector<gpu::CacheSimResult>>& by_pass, const gpu::FamilySpec& spec,
                   gpu::Frame frame) {
  auto sims = by_pass.find(pass.pass);
  const gpu::PassLoad* load = load_of(loads, pass.pass);
  if (sims != by_pass.end() && load) gpu::apply_cache_model(pass, *load, spec, frame, gpu::merge(sims->second));
}

// The simulated traffic of every traceable draw of `variant` on `family`, by pass: from `memo`, else the disk
// cache, else traced (the variant's missing draws in one render) and simulated, then kept in both.
std::map<std::string, std::vector<gpu::CacheSimResult>> draw_traffic(
    TraceSet& set, int variant, const std::string& family, const gpu::CacheHierarchy& hierarchy,
    const TrafficCache& cache, TrafficMemo& memo, TrafficStats& stats) {
  const auto draws = set.draws_of(variant);
  std::set<std::string> simulated;  // draws whose traffic is known (another variant's, an earlier call's): not traced
  bool complete = true;
  for (const auto& [key, pass] : draws)
    if (known(key, family, cache, memo, stats)) simulated.insert(key);
    else complete = false;
  if (!complete) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto traces = set.keyed(variant, simulated);
    stats.trace_seconds += seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    for (const auto& [key, trace] : traces) {
      auto [it, fresh] = memo.try_emplace({key, family});
      if (!fresh) continue;
      it->second.absent = trace == nullptr;
      if (trace) {
        it->second.result = gpu::simulate(*trace, hierarchy);
        ++stats.simulations;
      }
      cache.store(key, family, it->second);
    }
    stats.simulate_seconds += seconds_since(t1);
  }
  std::map<std::string, std::vector<gpu::CacheSimResult>> by_pass;
  for (const auto& [key, pass] : draws)
    if (const CachedTraffic& t = memo.at({key, family}); !t.absent) by_pass[pass].push_back(t.result);
  return by_pass;
}

}  // namespace

std::map<std::string, double> cached_pass_estimates(const table::GpuCost& cost,
                                                    const std::vector<std::pair<std::string, std::string>>& draws,
                                                    const std::vector<gpu::PassLoad>& loads, const std::string& family,
                                                    gpu::Frame frame, const TrafficCache& cache, TrafficMemo& memo,
                                                    TrafficStats& stats) {
  std::map<std::string, double> out;
  const gpu::FamilySpec* spec = gpu::estimate_spec(family);
  if (!spec || spec->caches.empty()) return out;
  std::set<std::string> unknown;  // passes with a draw not simulated yet
  std::map<std::string, std::vector<gpu::CacheSimResult>> by_pass;
  for (const auto& [key, pass] : draws)
    if (!known(key, family, cache, memo, stats)) unknown.insert(pass);
    else if (const CachedTraffic& t = memo.at({key, family}); !t.absent) by_pass[pass].push_back(t.result);
  for (table::GpuPassCost pass : cost.passes) {
    if (unknown.count(pass.pass)) continue;
    apply_traffic(pass, loads, by_pass, *spec, frame);
    out[pass.pass] = pass.est_ms;
  }
  return out;
}

std::string view_context(const scene::Scene& scene, const scene::View& view, float radius, gpu::Frame frame,
                         const TraceOptions& options) {
  return fmt::format("{}|{}|{}|{}x{}|{}", scene.content_hash, scene::camera_text(view), radius, frame.width,
                     frame.height, options.window_share);
}

TrafficStats add_traffic(runner::VariantRunner& runner, const std::vector<int>& variants, const scene::View& view,
                         float radius, const std::map<std::string, std::vector<gpu::PassLoad>>& loads,
                         gpu::Frame frame, std::map<std::string, table::GpuCosts>& costs,
                         const TraceOptions& options, const TrafficCache& cache, TrafficMemo* shared_memo) {
  TrafficStats stats;
  TraceSet set(runner, view, radius, options);
  TrafficMemo own_memo;
  TrafficMemo& memo = shared_memo ? *shared_memo : own_memo;
  for (int v : variants) {
    const std::string& key = runner.compiled().space.variants.at(v).key;
    auto row = costs.find(key);
    auto variant_loads = loads.find(key);
    if (row == costs.end() || variant_loads == loads.end()) continue;
    for (auto& [family, cost] : row->second) {
      const gpu::FamilySpec* spec = gpu::estimate_spec(family);
      if (!spec || spec->caches.empty()) continue;
      // The draws of each pass, simulated (once per draw and family) and merged.
      const auto by_pass = draw_traffic(set, v, family, gpu::hierarchy_of(*spec), cache, memo, stats);
      double total = 0;
      for (table::GpuPassCost& pass : cost.passes) {
        apply_traffic(pass, variant_loads->second, by_pass, *spec, frame);
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
