#pragma once
// The measuring core of `aovar measure`: per backend and view, rows whose inputs are unchanged are reused,
// the others are prepared in batches and timed round-robin with the baseline (measure/timing.h), then read
// back, scored against the view's ray-traced reference and written as images.
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "measure/measure.h"
#include "measure/inputs.h"
#include "measure/rows_json.h"
#include "runner/score.h"
#include "runner/variant_runner.h"

namespace aovar::measure {

// The selected variants after globs, shard, skip list, profile drops and dedup.
struct Selection {
  std::vector<int> measured;                           // one per group of identical variants
  std::map<int, std::vector<std::string>> duplicates;  // by measured variant: the identical selected ones
  int baseline = -1;                                   // timed in every round
  bool baseline_selected = false;                      // else its row is timing-only (is_baseline)
};

class BatchMeasurer {
 public:
  // Appends rows, runs and devices to `result`; every reference must outlive the measurer.
  BatchMeasurer(const MeasureOptions& options, const compile::CompiledSpace& compiled, const scene::Scene& scene,
                const Selection& selection, const PreviousRun& earlier, MeasureResult& result, const Progress& progress);

  // Earlier rows this run does not produce stay reusable (a narrower sweep, the first phase of a pruned one),
  // unless this run writes their image (same backend, view and variant: a row with other inputs).
  std::map<std::string, nlohmann::json> unproduced_rows(const std::vector<const scene::View*>& views) const;

  // Every backend and view; `after_batch` after each measured batch (the caller checkpoints).
  void measure_all(const std::vector<const scene::View*>& views, const std::function<void()>& after_batch);

  // Traces (or loads) the reference of every view whose copy under OUT/images/reference/ is missing.
  void store_references(const std::vector<const scene::View*>& views);

 private:
  struct Candidate {
    int variant;
    render::PipelinePlan plan;
    VariantInputs inputs;
  };
  struct Twin {  // a variant that runs its representative's code (same_code.h): not measured, copied
    int representative;
    Candidate cand;
  };
  // A backend's devices: its first, and those made when stills render side by side (TimingPlan::still_devices).
  struct StillDevices {
    runner::VariantRunner* first;
    runner::RunnerOptions options;  // the first's, for the others
    std::vector<std::unique_ptr<runner::VariantRunner>> more;
    runner::VariantRunner& at(std::size_t i, const scene::Scene& scene);  // made, with the scene, when first asked
  };
  struct BatchRows {  // one rendered batch: its run record, its rounds (the baseline's first), its rows
    RunRecord run;
    RoundRobinResult timed;
    std::vector<MeasureRow> rows;
  };
  void measure_view(StillDevices& devices, const scene::View& view, const std::function<void()>& after_batch);
  std::size_t still_devices(const runner::VariantRunner& runner, int batches) const;
  BatchRows run_batch(runner::VariantRunner& runner, render::PreparedPipeline& ref_pipeline, const Candidate& ref,
                      const std::vector<Candidate>& todo, std::size_t lo, std::size_t hi, const scene::View& view,
                      const std::string& where, TimingOptions& to, bool report);
  Candidate candidate(runner::VariantRunner& runner, int variant, const std::string& context) const;
  std::map<int, Twin> twins(runner::VariantRunner& runner, const scene::View& view, const std::string& context);
  bool twins_render_alike(runner::VariantRunner& runner, const scene::View& view, int representative, int twin);
  // Copies the rows of the twins whose representative's row now exists, and forgets those twins.
  void add_twin_rows(std::map<int, Twin>& twins, const render::DeviceInfo& device, const std::string& view);
  // `device`: the runner's (backend, device and driver go into the row).
  MeasureRow new_row(const Candidate& cand, const render::DeviceInfo& device, const std::string& view) const;
  bool reuse(const Candidate& cand, const render::DeviceInfo& device, const std::string& view);
  void finish_row(MeasureRow& row, runner::VariantRunner& runner, const Candidate& cand, render::PreparedPipeline& p,
                  const PipelineTiming& timing, const scene::View& view);
  void temporal_errors(MeasureRow& row, runner::VariantRunner& runner, const render::PipelinePlan& plan,
                       render::PreparedPipeline& p, const scene::View& view);
  std::string context(const runner::VariantRunner& runner, const scene::View& view) const;
  // The race's rule for one batch (timing.h, Retire): the reference, then todo[lo, hi), by known error on `view`,
  // and the view's rows of the batches before (`earlier`); with TimingPlan::race_budget the reference is the
  // budget, and what is slower than it beyond the margin retires.
  Retire retire_rule(const Candidate& reference, const std::vector<Candidate>& todo, std::size_t lo, std::size_t hi,
                     const std::string& view, const std::vector<EarlierRow>& earlier) const;
  RoundRobinResult render_batch(runner::VariantRunner& runner, const std::vector<render::PreparedPipeline*>& pipelines,
                                const std::vector<int>& still_frames, const scene::View& view, TimingOptions& to,
                                const std::string& where, bool report);
  void score_unknown_errors(runner::VariantRunner& runner, const std::vector<render::PreparedPipeline*>& pipelines,
                            const scene::View& view, Retire& rule);
  const reference::ReferenceImage& ground_truth(const scene::View& view);
  const runner::ViewScorer& scorer(const scene::View& view);  // against ground_truth(view)
  void status(const std::string& what) const;

  const MeasureOptions& o_;
  const compile::CompiledSpace& c_;
  const scene::Scene& scene_;
  const Selection& sel_;
  const PreviousRun& earlier_;
  MeasureResult& res_;
  Progress progress_;
  std::map<std::string, reference::ReferenceImage> truth_;
  std::map<std::string, runner::ViewScorer> scorers_;  // each refers to its view's truth_ entry
  std::map<std::string, bool> twins_alike_;  // by backend: its first twin pair rendered bit-identical images
  std::size_t rows_wanted_ = 0, rows_measured_ = 0;
  std::chrono::steady_clock::time_point measuring_start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_measured_ = measuring_start_;  // when rows_measured_ last grew
};

}  // namespace aovar::measure
