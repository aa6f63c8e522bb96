#pragma once
// Round-robin timing of prepared pipelines on one backend and view (docs/architecture.md, "Rendering and timing"): each pipeline's first
// frame (JIT) is timed on its own, warm-up frames are discarded, then every round renders each pipeline
// once, in an order rotated per round, so drift on a noisy machine spreads over all of them. The
// reference pipeline is part of every round, so each result can be given relative to it.
#include <functional>
#include <string>
#include <vector>

#include "util/stats.h"
#include "render/backend.h"

namespace aovar::measure {

struct TimingOptions {
  int warmup = 2;   // frames after the first (JIT) frame that are discarded
  int reps = 10;    // timed rounds
  float radius = 1.0f;
  bool camera_path = false;  // frames walk the view's camera path (else its first pose, static)
};

struct PipelineTiming {
  double first_frame_ms = 0;                 // first frame: includes the driver's JIT of every draw
  std::vector<std::vector<double>> draw_ms;  // [round][draw]
  std::vector<double> total_ms;              // [round] sum of the draws
  int frames = 0;                            // frames rendered so far (the next frame's number)
};

struct RoundRobinResult {
  std::vector<PipelineTiming> pipelines;
  double wall_timed_s = 0;  // wall time of the timed rounds (rendering, uploads, waits, read-outs)
  double sum_timed_s = 0;   // the summed draw times those rounds reported
  double wall_warmup_s = 0; // first frames and warm-up
};

using Progress = std::function<void(const std::string&)>;

// Times every pipeline in `pipelines` (all prepared on `backend` for `view`) round-robin.
RoundRobinResult time_round_robin(render::Backend& backend, const std::vector<render::PreparedPipeline*>& pipelines,
                                  const scene::View& view, const TimingOptions& options,
                                  const Progress& progress = {});

// Per timing group ("gbuffer", "ao", "blur", ...): stats of the summed draw times of that group per round.
std::vector<std::pair<std::string, util::TimeStats>> pass_stats(const render::PipelinePlan& plan, const PipelineTiming& t);

// Median over rounds of this pipeline's total divided by the reference's total in the same round.
double median_ratio(const PipelineTiming& t, const PipelineTiming& reference);

}  // namespace aovar::measure
