#pragma once
// Round-robin timing of prepared pipelines on one backend and view (docs/architecture.md, "Rendering and timing"): each pipeline's first
// frame (JIT) is timed on its own, warm-up frames are discarded, then every round renders each pipeline
// once, in an order rotated per round, so drift on a noisy machine spreads over all of them. The
// reference pipeline is part of every round, so each result can be given relative to it.
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "util/stats.h"
#include "render/backend.h"

namespace aovar::measure {

// --reps auto: rounds go on until every pipeline's ratio to the reference is known to within ci_target, or
// the pipeline has had its cap. `reps` (TimingOptions, MeasureOptions) is then the least number of rounds,
// so auto never measures less than the fixed default.
struct AutoReps {
  double ci_target = 0.02;  // (hi - lo) / 2 / median of the 95 % interval of the per-round ratio
  double cap_s = 2.0;       // per pipeline: its own timed frames, summed, after which it stops anyway
  int max_rounds = 200;     // per pipeline, whatever the cap in seconds says
  bool operator==(const AutoReps&) const = default;
};

// Racing (aovar ship's race; the idea of F-race, Birattari et al. 2002): with --reps auto, a pipeline whose
// error is known stops being timed once another pipeline of its batch with a lower known error is faster
// beyond `margin`: the 95 % sign-test interval of their per-round time ratio lies wholly at or above it
// (or a row of an earlier batch is, against the reference: EarlierRow below).
// More rounds would only narrow an interval the race no longer needs; the rounds it had stay in its row.
// With `reference_is_budget` the reference is also the budget of a selection (ship's held-out views under
// --budget-of): a pipeline slower than it beyond `margin` cannot be chosen, whatever its error, and retires.
// Rows timed in earlier batches of the same view count too (`earlier`): they share no rounds with this batch,
// but every batch times the reference, so a pipeline retires once the low end of its interval against the
// reference is at or above `margin` times the high end of a more accurate earlier row's (disjoint intervals).
struct EarlierRow {
  double known_error = NAN;
  double ratio_hi = NAN;  // high end of its 95 % interval of the per-round ratio to the reference
};

struct Retire {
  std::vector<double> known_error;  // per pipeline, as ordered for time_round_robin; NaN: unknown (never compared)
  double margin = 1.0;
  bool reference_is_budget = false;
  std::vector<EarlierRow> earlier{};  // the view's rows timed in earlier batches (against the same reference)
};

struct TimingOptions {
  int warmup = 2;   // frames after the first (JIT) frame that are discarded
  int reps = 10;    // timed rounds (with `adaptive`: the least number)
  float radius = 1.0f;
  bool camera_path = false;  // frames walk the view's camera path (else its first pose, static)
  std::optional<AutoReps> adaptive;  // --reps auto
  std::optional<Retire> retire;      // with `adaptive` only
};

// Why a pipeline's timing ended: a fixed --reps N, its interval reached the target, its cap, or a more
// accurate pipeline was faster beyond the race's margin (Retire).
enum class Stop { running, fixed, target, cap, dominated };
const char* stop_name(Stop s);  // "running", "fixed", "target", "cap", "dominated"
Stop stop_from_name(const std::string& name);  // unknown names: fixed (rows written before --reps auto)

struct PipelineTiming {
  double first_frame_ms = 0;                 // first frame: includes the driver's JIT of every draw
  std::vector<std::vector<double>> draw_ms;  // [round][draw]
  std::vector<double> total_ms;              // [round] sum of the draws
  int frames = 0;                            // frames rendered so far (the next frame's number)
  Stop stop = Stop::running;
};

struct RoundRobinResult {
  std::vector<PipelineTiming> pipelines;
  double wall_timed_s = 0;  // wall time of the timed rounds (rendering, uploads, waits, read-outs)
  double sum_timed_s = 0;   // the summed frame times those rounds reported (a shared G-buffer in each frame reading it)
  double wall_warmup_s = 0; // first frames and warm-up
};

using Progress = std::function<void(const std::string&)>;

// Times every pipeline in `pipelines` (all prepared on `backend` for `view`) round-robin: warm_up, then
// time_rounds. Each round first draws every shared G-buffer its pipelines read once (render/gbuffer_share.h);
// each pipeline's frame then reports that draw's time in its G-buffer draw's place.
RoundRobinResult time_round_robin(render::Backend& backend, const std::vector<render::PreparedPipeline*>& pipelines,
                                  const scene::View& view, const TimingOptions& options,
                                  const Progress& progress = {});

// Its two halves, for a caller that reads the pipelines between the warm-up and the rounds.
// With `stills` (the race scores each still, TimingPlan::race_scores_stills): every pipeline first renders its
// still, `frames[i]` frames (2 for a progressive one, whose halves alternate; its first timed on its own), then
// `read` runs, then every pipeline renders its `warmup` frames. The warm-up comes after the read-back, so that no
// timed frame is a pipeline's first after it (the reference's, first in round 1, took about 1.5x as long on the Vulkan CPU backend).
// Without, each pipeline's first frame and warm-up frames, one pipeline after the other.
struct StillsBeforeWarmUp {
  std::vector<int> frames;
  std::function<void()> read;
};
RoundRobinResult warm_up(render::Backend& backend, const std::vector<render::PreparedPipeline*>& pipelines,
                         const scene::View& view, const TimingOptions& options, const StillsBeforeWarmUp* stills);
void time_rounds(render::Backend& backend, const std::vector<render::PreparedPipeline*>& pipelines,
                 const scene::View& view, const TimingOptions& options, RoundRobinResult& warmed,
                 const Progress& progress = {});

// TimingPlan::still_only: every pipeline renders the frames its still needs, `frames[i]` (2 for a
// progressive one, whose halves alternate; else 1), and nothing is timed: no rounds, Stop::fixed. The first
// frame's time is kept (first_frame_ms) as time_round_robin keeps it.
RoundRobinResult render_stills(render::Backend& backend, const std::vector<render::PreparedPipeline*>& pipelines,
                               const std::vector<int>& frames, const scene::View& view, const TimingOptions& options);

// Per timing group ("gbuffer", "ao", "blur", ...): stats of the summed draw times of that group per round.
std::vector<std::pair<std::string, util::TimeStats>> pass_stats(const render::PipelinePlan& plan, const PipelineTiming& t);

// Per round: the pipeline's frame time over the reference's in the same round (table::Rounds). A pipeline
// that stopped early has fewer rounds; its round i is still the reference's round i.
std::vector<double> round_ratios(const PipelineTiming& t, const PipelineTiming& reference);

// Median over rounds of this pipeline's total divided by the reference's total in the same round.
double median_ratio(const PipelineTiming& t, const PipelineTiming& reference);

// The relative half-width (hi - lo) / 2 / median of the 95 % sign-test interval of the median of `ratios`;
// NaN below the samples that interval needs.
double relative_half_width(const std::vector<double>& ratios);

// The stopping rule of --reps auto, after a round (no timing in it, so it is tested on synthetic rounds):
// pipelines[0] is the reference, the others have run every round since the first until they stopped. A
// running pipeline with at least `min_rounds` rounds stops on the target when its relative half-width is
// within `rule.ci_target`, else on the cap when its timed frames reach cap_s or its rounds max_rounds. The
// reference stops only when no other pipeline runs: every ratio needs it in the same round. With `retire`,
// a running pipeline that neither target nor cap stopped, with at least `min_rounds` rounds, stops as
// dominated when Retire's rule says so (the reference is never retired, but may retire others).
void stop_after_round(std::vector<PipelineTiming>& pipelines, int min_rounds, const AutoReps& rule,
                      const Retire* retire = nullptr);

}  // namespace aovar::measure
