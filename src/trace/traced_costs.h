#pragma once
// The GPU estimate of variants on one scene view (issue 33): each variant's fullscreen draws traced on the
// view (trace/trace_set.h: a draw shared by several variants is traced once), each trace replayed through
// each family's caches (gpu/cache_sim.h, memoised per trace and family), the draws of a pass merged, and the
// pass's roofline redone on the simulated traffic (gpu/cache_estimate.h). The estimate then depends on the
// scene and the view, and names the view it was traced on (table::GpuCost::view).
#include <map>
#include <string>
#include <vector>

#include "gpu/costs.h"
#include "trace/trace_set.h"
#include "trace/traffic_cache.h"

namespace aovar::trace {

struct TrafficStats {
  int traced_draws = 0, shared_draws = 0, simulations = 0;
  int cached_draws = 0;  // (draw, family) results read from the disk cache (traffic_cache.h)
  double trace_seconds = 0, simulate_seconds = 0;
  TrafficStats& operator+=(const TrafficStats& o) {
    traced_draws += o.traced_draws, shared_draws += o.shared_draws, simulations += o.simulations;
    cached_draws += o.cached_draws;
    trace_seconds += o.trace_seconds, simulate_seconds += o.simulate_seconds;
    return *this;
  }
};

// Simulated traffic by (draw key, family), of one view: what add_traffic keeps between draws, and a caller between
// calls on the same view (draw keys do not name the view; view_context does).
using TrafficMemo = std::map<std::pair<std::string, std::string>, CachedTraffic>;

// `costs`: variant key -> family -> cost with statistics and roofline (gpu::costs_of) for the same variants
// and frame; every family there with a product spec gets the traffic model, the others are left as they are.
// `loads`: gpu::variant_loads of the same variants. The runner renders at the estimate's frame size.
// `cache`: draws simulated by an earlier run on the same view (TrafficCache; default: none). `memo`: the
// traffic of this view simulated by earlier calls, filled by this one (null: this call's own).
TrafficStats add_traffic(runner::VariantRunner& runner, const std::vector<int>& variants, const scene::View& view,
                         float radius, const std::map<std::string, std::vector<gpu::PassLoad>>& loads,
                         gpu::Frame frame, std::map<std::string, table::GpuCosts>& costs,
                         const TraceOptions& options = {}, const TrafficCache& cache = TrafficCache({}, ""),
                         TrafficMemo* memo = nullptr);

// What add_traffic would give the passes of one variant on `family` whose every draw `memo` or `cache` already
// holds, without rendering: pass -> est_ms. `cost`: the variant's cost on the family before any traffic;
// `draws`: TraceSet::draws_of its plan; `loads`: its gpu::PassLoad. A pass with a draw not simulated yet is
// absent; so is every pass when the family has no cache model. Draws read from `cache` count in `stats`.
std::map<std::string, double> cached_pass_estimates(const table::GpuCost& cost,
                                                    const std::vector<std::pair<std::string, std::string>>& draws,
                                                    const std::vector<gpu::PassLoad>& loads, const std::string& family,
                                                    gpu::Frame frame, const TrafficCache& cache, TrafficMemo& memo,
                                                    TrafficStats& stats);

// What a TrafficCache of one view is keyed by besides the draw: the scene's geometry, the camera, the radius,
// the frame and the trace window.
std::string view_context(const scene::Scene& scene, const scene::View& view, float radius, gpu::Frame frame,
                         const TraceOptions& options);

}  // namespace aovar::trace
