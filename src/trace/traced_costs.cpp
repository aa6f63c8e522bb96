#include "trace/traced_costs.h"

#include <chrono>
#include <memory>
#include <cmath>
#include <set>
#include <utility>

#include "gpu/cache_estimate.h"
#include "gpu/family_specs.h"
#include "scene/scene.h"
#include "trace/simulation_queue.h"

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

// The families of a variant's costs that have a cache model, with their hierarchies.
std::vector<std::pair<std::string, gpu::CacheHierarchy>> modelled(const table::GpuCosts& costs) {
  std::vector<std::pair<std::string, gpu::CacheHierarchy>> out;
  for (const auto& [family, cost] : costs)
    if (const gpu::FamilySpec* spec = gpu::estimate_spec(family); spec && !spec->caches.empty())
      out.emplace_back(family, gpu::hierarchy_of(*spec));
  return out;
}

// Traces the draws of `variant` whose traffic on some family is not known yet (memo, else the disk cache), in one
// render, and queues their simulations; the memo gets their entries now (so no later variant traces them again),
// their results once `queue` finishes. `fresh`: the (draw, family) entries made, for the disk cache.
void trace_unknown(TraceSet& set, int variant, const std::vector<std::pair<std::string, std::string>>& draws,
                   const std::vector<std::pair<std::string, gpu::CacheHierarchy>>& families, const TrafficCache& cache,
                   TrafficMemo& memo, TrafficStats& stats, SimulationQueue& queue,
                   std::vector<std::pair<std::string, std::string>>& fresh) {
  std::map<std::string, std::vector<const std::pair<std::string, gpu::CacheHierarchy>*>> wanted;  // draw -> families
  for (const auto& [key, pass] : draws)
    for (const auto& f : families)
      if (!known(key, f.first, cache, memo, stats)) wanted[key].push_back(&f);
  if (wanted.empty()) return;
  std::set<std::string> skip;  // draws whose traffic is known on every family (another variant's, an earlier call's)
  for (const auto& [key, pass] : draws)
    if (!wanted.count(key)) skip.insert(key);
  const auto t0 = std::chrono::steady_clock::now();
  const auto traces = set.keyed(variant, skip);
  stats.trace_seconds += seconds_since(t0);
  for (const auto& [key, trace] : traces) {
    std::shared_ptr<const gpu::FetchTrace> owned = trace ? set.take(key) : nullptr;
    for (const auto* family : wanted[key]) {
      auto [it, made] = memo.try_emplace({key, family->first});
      if (!made) continue;
      it->second.absent = owned == nullptr;
      fresh.emplace_back(key, family->first);
      if (!owned) continue;
      queue.add(owned, family->second, &it->second.result);
      ++stats.simulations;
    }
  }
}

// The simulated traffic of a variant's draws on `family`, by pass (every draw in `memo`).
std::map<std::string, std::vector<gpu::CacheSimResult>> traffic_by_pass(
    const std::vector<std::pair<std::string, std::string>>& draws, const std::string& family, const TrafficMemo& memo) {
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
  struct Estimated {
    table::GpuCosts* costs;
    const std::vector<gpu::PassLoad>* loads;
    std::vector<std::pair<std::string, std::string>> draws;
  };
  std::vector<Estimated> estimated;
  std::vector<std::pair<std::string, std::string>> fresh;
  try {
    // Every unknown draw traced (once per draw) and simulated (once per draw and family), the simulations on a
    // worker while the next variant traces.
    SimulationQueue queue;
    for (int v : variants) {
      const std::string& key = runner.compiled().space.variants.at(v).key;
      auto row = costs.find(key);
      auto variant_loads = loads.find(key);
      if (row == costs.end() || variant_loads == loads.end()) continue;
      const auto families = modelled(row->second);
      if (families.empty()) continue;
      estimated.push_back({&row->second, &variant_loads->second, set.draws_of(v)});
      trace_unknown(set, v, estimated.back().draws, families, cache, memo, stats, queue, fresh);
    }
    stats.simulate_seconds += queue.finish();
  } catch (...) {
    for (const auto& entry : fresh) memo.erase(entry);  // made before their results: none may be read later
    throw;
  }
  for (const auto& [draw, family] : fresh) cache.store(draw, family, memo.at({draw, family}));
  // Each pass's draws merged, and its roofline redone on their traffic.
  for (const Estimated& e : estimated)
    for (auto& [family, cost] : *e.costs) {
      const gpu::FamilySpec* spec = gpu::estimate_spec(family);
      if (!spec || spec->caches.empty()) continue;
      const auto by_pass = traffic_by_pass(e.draws, family, memo);
      double total = 0;
      for (table::GpuPassCost& pass : cost.passes) {
        apply_traffic(pass, *e.loads, by_pass, *spec, frame);
        total += pass.est_ms;
      }
      cost.est_ms = total;
      cost.view = view.name;
    }
  stats.traced_draws = set.traced_draws();
  stats.shared_draws = set.shared_draws();
  return stats;
}

}  // namespace aovar::trace
