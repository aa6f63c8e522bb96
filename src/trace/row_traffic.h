#pragma once
// The traced estimate on cost-table rows (issue 33): every row with GPU costs (gpu::costs_by_key) gets its
// variant traced on the row's own scene and view at the estimate's frame size, and each family's estimate redone
// on the simulated traffic (trace/traced_costs.h). measure --gpu and sweep --gpu call it after costs_by_key; a
// row's estimate then names its view (table::GpuCost::view).
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compile/run_scope.h"
#include "gpu/by_key.h"
#include "render/plan.h"
#include "table/table.h"
#include "trace/traced_costs.h"

namespace aovar::scene {
struct Scene;
}
namespace aovar::runner {
class VariantRunner;
}

namespace aovar::trace {

// What a user asks of the GPU estimate (--gpu, --gpu-size, --gpu-trace, --gpu-window).
struct GpuEstimateOptions {
  std::vector<std::string> families;  // empty: no estimate
  render::Extent frame{1920, 1080};
  bool trace = true;                  // the estimate on each row's traced view; off: the view-free roofline
  double window = 0.5;                // share of each draw's width and height traced (a centred window)
};

// The estimate on rows: what is asked (`gpu`), in which run (`scope`: the rows' manifest, the cache root,
// the rendering threads), and how the rows were rendered, so that a trace sees what was measured.
struct RowGpuRequest {
  compile::RunScope scope;
  GpuEstimateOptions gpu;
  std::filesystem::path views_file;                           // the scenes' views side file (as measured)
  float radius = 0;                                           // world units; 0 = each scene's default
  std::map<std::string, render::ParamOverrides> calibration;  // as the rows were rendered
};

// The traced estimate on rows with GPU costs, at request.gpu's frame and window. Throws std::runtime_error
// (a scene or view that does not load, a variant that does not compile) or render::BackendError (no
// tracing backend).
TrafficStats add_row_traffic(const std::vector<table::CostRow*>& rows, const RowGpuRequest& request);

// add_row_traffic over many calls on the rows of one screen (ship's bounded estimate, a chunk of candidates at a
// time): each scene is loaded once, and each draw simulated once per view and family across the calls, kept
// in memory as well as in the cache dir. `cached` tells, without rendering, what the traffic simulated so far
// already gives.
class RowTracer {
 public:
  explicit RowTracer(RowGpuRequest request);
  ~RowTracer();
  RowTracer(const RowTracer&) = delete;
  RowTracer& operator=(const RowTracer&) = delete;

  // The variants later calls will ask for: compiled with the first call's, once, rather than a chunk at a time.
  void expect(const std::set<std::string>& keys);
  TrafficStats trace(const std::vector<table::CostRow*>& rows);  // add_row_traffic
  // Per row of `rows` (in order), pass -> its traced estimate on `family`, for the passes whose every draw on the
  // row's view was simulated by an earlier call or an earlier run (trace::cached_pass_estimates). Renders nothing.
  std::vector<std::map<std::string, double>> cached(const std::vector<table::CostRow*>& rows,
                                                    const std::string& family);

  struct Compiled;  // the rows' variants compiled for tracing (row_traffic.cpp)

 private:
  struct View;
  View& view_of(const table::CostRow& row);
  // The last compilation when it holds `keys` (else one of them and the expected), their loads analysed.
  Compiled& compiled_for(const std::set<std::string>& keys);
  // The trace runner on the current compilation, kept across calls: its pipelines and G-buffers serve the next.
  runner::VariantRunner& runner();
  RowGpuRequest request_;
  std::unique_ptr<Compiled> compiled_;
  std::set<std::string> expected_;
  TrafficStats read_ahead_;  // draws `cached` read from the cache dir: reported by the next `trace`
  std::set<std::string> compiled_keys_;
  std::map<std::string, std::unique_ptr<scene::Scene>> scenes_;                  // by scene spec, loaded once
  std::map<std::pair<std::string, std::string>, std::unique_ptr<View>> views_;  // (scene, view)
  std::unique_ptr<runner::VariantRunner> runner_;  // last: destroyed before the compilation and scenes it reads
};

// `measure --gpu` and `sweep --gpu`: each row's ISA statistics and roofline per family (gpu::costs_by_key),
// then, unless gpu.trace is off, the traced estimate on its view. `say` gets the progress lines.
struct RowGpuResult {
  std::vector<std::string> errors;  // one line per family that failed (gpu::KeyedCosts::errors)
  std::string mesa;
  int pipelines = 0;
  double seconds = 0;  // statistics
  TrafficStats traffic;
  std::vector<std::string> families;
  std::string frame;         // "1920x1080"
  bool traced = false;
  double window_share = 1;
  nlohmann::json to_json() const;  // the table's and measure.json's "gpu" meta, with the request's families and frame
};
RowGpuResult add_gpu_costs(const std::vector<table::CostRow*>& rows, const RowGpuRequest& request,
                           const std::function<void(const std::string&)>& say);

}  // namespace aovar::trace
