#pragma once
// `aovar measure`: compile the selected variants, render each one's full AO pipeline on a scene's views
// through the chosen backends, time them round-robin against a baseline variant, and write
// measure.json plus a float image (PFM) and an 8-bit preview (PNG) per variant, view and backend.
// Rows are keyed by a hash of everything that determines them, so an interrupted or repeated run reuses
// what it already measured, whatever else it selects (measure.json is rewritten atomically after every batch).
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compile/run_scope.h"
#include "measure/timing.h"
#include "metrics/metrics.h"
#include "profile/scene_prune.h"
#include "reference/reference.h"
#include "render/backend.h"
#include "table/table.h"
#include "trace/row_traffic.h"

namespace aovar::measure {

using profile::ScenePruning;

// The default baseline variant (timed in every round): Alchemy, 8 samples, the mobile-typical buffers (Sunet 2018's configuration).
inline constexpr const char* kDefaultBaseline = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";

// How rows are timed (timing.h runs it): round-robin rounds against the baseline in batches.
struct TimingPlan {
  int reps = 10;                      // timed rounds; with auto_reps the least number of them
  std::optional<AutoReps> auto_reps;  // --reps auto: rounds until each row's interval is narrow (timing.h)
  int warmup = 2;
  int batch = 24;                     // pipelines prepared and interleaved at once (memory bound)
  bool camera_path = false;           // frames walk each view's camera path (progressive in motion)
  // No timed rounds: each variant renders only the frames its still needs and its rows carry no time
  // (time_ms.n = 0). aovar ship's screen with a GPU target, whose time is the estimate (render_stills).
  bool still_only = false;
  // With still_only, on a backend that runs side by side (render::BackendInfo::side_by_side): devices that render
  // a view's batches at once, batch b on device b % still_devices, the rows kept in batch order. lavapipe
  // compiles a pipeline's shaders with LLVM on its one queue thread at its first draw, and the stills wait on
  // that: two devices on two cores took half the wall time of one (bench/README, "Views in turn").
  int still_devices = 1;
  // aovar ship's race: the still error each variant already showed on each view (its screen), by (key, view).
  // With auto_reps, a variant stops being timed on a view once a more accurate one of its batch, or of an
  // earlier batch, is faster beyond race_margin there (timing.h, Retire). Null: every row is timed to its
  // target or cap.
  std::shared_ptr<const std::map<std::pair<std::string, std::string>, double>> race_errors;
  // The order the race times a view's variants in, by (key, view): lower first, absent last (then key order).
  // A row retires only against a more accurate one timed in its batch or before it (Retire::earlier), so
  // what is likely on the front goes first: ship ranks by the screen's timed rows (race.h, screen_ranks).
  std::shared_ptr<const std::map<std::pair<std::string, std::string>, int>> race_order;
  double race_margin = 1.0;
  // The baseline is a selection's budget (ship's held-out views under --budget-of): with auto_reps, a variant
  // slower than it beyond race_margin stops being timed, whatever its error: it cannot be chosen.
  bool race_budget = false;
  // The race scores the stills itself (ship's race when no screen ran before it, every candidate fitting one
  // batch): each pipeline whose error race_errors does not hold renders its still, is read back and scored
  // against the reference before its warm-up and the timed rounds (timing.h, warm_up), and is raced by that error
  // (the baseline too, when selected). Needs GroundTruth::enabled.
  bool race_scores_stills = false;
  bool races() const { return race_errors || race_budget || race_scores_stills; }
};

// Ground truth (--reference): every row gets `error` against a ray-traced reference of its view at the
// measured size and radius (traced once per view, cached under `cache` when set).
struct GroundTruth {
  bool enabled = false;
  int rays = 256;
  reference::Mode mode = reference::Mode::occlusion;  // cached under the run scope's cache root
  // Each row's flicker along its view's camera path, and a progressive variant's error from one frame
  // (view.path_frames more renders a row), but for a row the race retired (Stop::dominated: off the front).
  // false: the still error only (ship's screening).
  bool temporal = true;
};

struct MeasureOptions {
  compile::RunScope scope;                 // the manifest, rendering threads, compile jobs, the cache root
  // What is measured: the scene, its views, the backends, and which variants.
  std::string scene = "builtin:atrium";
  std::filesystem::path views_file;        // side file for the scene's views (optional)
  std::vector<std::string> views;          // empty: the scene's first view (overview)
  std::vector<std::string> backends = {render::default_backend()};
  std::vector<std::string> globs;          // --variants
  std::string baseline = kDefaultBaseline;  // timed in every round (rel_time = 1); falls back to the first selected variant when absent
  // Variant keys the globs select but not to measure (sweep --prune-dominated); the baseline is still timed.
  std::set<std::string> skip;
  // A shard's share of the selection, as sweep's cost-balanced plan chose it (sweep/shard_plan.h, the one
  // planner of a sharded measurement); null: every selected variant. The baseline is timed regardless.
  std::shared_ptr<const std::set<std::string>> shard_keys;
  bool in_shard(const std::string& key) const { return !shard_keys || shard_keys->count(key) > 0; }
  // What the scene's profile drops (scene_prune.h), computed by the caller: sweep over all its scenes'
  // selections, measure_scene with prune_by_profile below; null: nothing pruned. The
  // dropped variants are neither compiled nor measured and are listed in measure.json's "pruned" section
  // with their reasons (the baseline, when dropped, is still timed as the pairing reference: a timing-only row).
  std::shared_ptr<const ScenePruning> pruning;

  // How it is rendered.
  render::Extent size{640, 360};
  std::string device;                      // the Vulkan backend: --device NAME|INDEX (render::BackendOptions::device)
  bool share_gbuffer = true;               // one G-buffer per format (render::BackendOptions::share_gbuffer)
  float radius = 0;                        // world units; 0 = the scene's default
  render::ParamOverrides params;           // "<pass>.<name>" -> value
  // Calibrated parameter values (aovar calibrate), where they came from and what measure.json and the cost
  // table record of them; empty: the manifest's defaults. --param wins over them.
  table::CalibrationRef calibration;

  TimingPlan timing;
  GroundTruth truth;

  // Where it goes.
  std::filesystem::path out;               // empty: no files (tests)
  bool images = true;
  bool contact_sheets = true;              // with images; false leaves the earlier sheets (sweep's pruning phases)
  bool reuse = true;                       // keep rows of an earlier measure.json whose inputs match
};

// What fails before any scene is loaded: the options' own rules, and each --param against the manifest (a
// parameter some selected variant has, inside its range). run_measure checks it too; a caller that profiles
// the scene first (the measure command) calls it before, so a bad option costs no profile.
void check_request(const MeasureOptions& options);

// The views a measurement renders: each named one once, in the order given; none named: the scene's first.
std::vector<const scene::View*> chosen_views(const scene::Scene& scene, const std::vector<std::string>& names);

// What the scene's profile drops on the views measurement `options` renders (chosen_views), profiled in its
// run scope at its size and radius, stored in its output folder and reused from there. `covered`: the globs
// the pruning lists cover (the run's --variants, and sweep's --predict; empty: every variant).
std::shared_ptr<const ScenePruning> prune_by_profile(const MeasureOptions& options, const scene::Scene& scene,
                                                     const std::vector<std::string>& covered, const Progress& progress);

// The reference a measurement scores a view against: its size, rays, mode and cache root, at `radius` (the
// options' or the scene's), on the frame its images show (the last of the camera path, else 0).
reference::ReferenceOptions reference_options(const MeasureOptions& options, float radius);

// The GPU estimate on a measurement's rows (trace::add_gpu_costs): in its run scope, rendered as it rendered.
trace::RowGpuRequest gpu_request(const MeasureOptions& options, const trace::GpuEstimateOptions& gpu);

// --reps as the inputs hash and the text output hold it: "10", or "auto" with its minimum, target and caps
// (a row timed to a 2 % target is not one timed to 1 %, nor one of a fixed count).
std::string reps_text(const MeasureOptions& options);

// In words: "10 reps", or "--reps auto (95 % interval within 2 %, at least 10 rounds, cap 2 s or 200 rounds)".
std::string reps_words(const MeasureOptions& options);

// The rule of --reps auto in measure.json and cost_table.json meta: {"min_rounds", "ci_target", "cap_s",
// "max_rounds"}, or null for a fixed --reps N.
nlohmann::json reps_auto_json(const MeasureOptions& options);

// The calibration measure.json and cost_table.json meta record: {"file", "hash"}, or null for none.
nlohmann::json calibration_json(const MeasureOptions& options);

// A measured row: the cost-table row (variant, axes, scene, view, backend, size, threads, time_ms with its
// paired time, rel_time, error, health, flicker, images) and how it was measured.
struct MeasureRow : table::CostRow {
  std::vector<std::string> duplicates;  // selected variants with the same programs (not measured again)
  std::string inputs_hash;              // programs, plan, key, scene, view, backend, device, size, threads,
                                        // reps, warmup, radius, parameters, baseline, reference key (inputs.h)
  std::vector<std::pair<std::string, util::TimeStats>> passes;
  std::string baseline;                 // the variant timed in every round with this one
  bool is_baseline = false;             // the baseline, measured although no --variants glob selected it
  double create_ms = 0, first_frame_ms = 0, jit_ms = 0;
  double mean_visibility = 0;
  // Progressive variants with --reference: the error of one frame alone (its half of the samples, no
  // history); `error` is then the converged error (both halves averaged on a static camera).
  std::optional<metrics::ErrorStats> error_one_frame;
  std::string image, preview, error_map;  // paths relative to the output folder (`images` lists them)
  image::FloatImage result;             // kept in memory for callers (tests); not serialised
  bool reused = false;
  // What the timing reached: the relative half-width of the interval of rounds.ratios (reps reached: their
  // count) and why it ended (--reps auto: target or cap; --reps N: fixed).
  double ci_half_width = NAN;
  Stop stop = Stop::fixed;

  void list_images();  // images = the non-empty of image, preview, error_map
  // passes, and gbuffer_ms from its "gbuffer" group (the format's G-buffer draw of each round; unknown
  // without timed rounds): the one way both are set, so the table's split is the passes' own figure.
  void set_passes(std::vector<std::pair<std::string, util::TimeStats>> per_group);
  void set_reps_reached(Stop why);  // ci_half_width from rounds.ratios
};

// Over rows (the baseline's timing-only one left out): the widest half-width reached and how many stopped
// on the cap, for the text output and the meta of measure.json and cost_table.json.
struct RepsReached {
  int rows = 0, on_cap = 0;
  int dominated = 0;  // raced rows stopped as dominated (Stop::dominated), kept out of `widest`
  double widest = 0;  // relative half-width; 0 when no row has an interval
  std::vector<double> rounds;  // per row: rounds reached
  void add(const MeasureRow& row);
  nlohmann::json to_json() const;  // {"rows", "on_cap", "dominated", "widest_half_width", "rounds_median", "rounds_max"}
  std::string text() const;        // "widest 95 % half-width 1.8 %, 0 of 75 rows on the cap, rounds median 14, max 200"
};

struct RunRecord {  // one batch on one backend and view: where the time went
  std::string backend, view;
  int pipelines = 0;
  int device = 0;  // which of the backend's devices rendered it (TimingPlan::still_devices; else 0)
  double prepare_s = 0, warmup_s = 0, timed_wall_s = 0, timed_sum_s = 0, readback_s = 0;
};

struct MeasureResult {
  std::string scene, scene_hash;
  std::size_t triangles = 0;
  float radius = 0;
  std::vector<render::DeviceInfo> devices;
  std::vector<MeasureRow> rows;
  std::vector<RunRecord> runs;
  std::string counts;  // "space N / rules R / selected S / dedup D"
  std::vector<std::string> contact_sheets;  // per backend and view with 2+ images, relative to the output folder
  std::string contact_sheets_rows;          // fingerprint of the rows the sheets show
  // Rows of the earlier measure.json this run did not select, as JSON: still reusable by a later run.
  nlohmann::json kept_rows;
  double wall_s = 0, compile_s = 0;
  int reused = 0;
  std::shared_ptr<const ScenePruning> pruning;  // the options' pruning, when given
  // A GPU estimate of the rows, when the caller made one (run_measure estimates nothing itself: measure_scene
  // and sweep add it, gpu_request): trace::RowGpuResult::to_json(), null without.
  nlohmann::json gpu_meta;
};

RepsReached reps_reached(const MeasureResult& result);

// The table's rows of a measurement (every row but the baseline's timing-only one), images relative to
// `prefix` (sweep: measure/<scene folder>).
std::vector<table::CostRow> cost_rows(const MeasureResult& result, const std::filesystem::path& prefix = {});

// Throws std::runtime_error (and the scene/manifest/backend errors) with one-line messages. `progress`
// gets transient status lines, and lines starting "note: " that a user should see even without a terminal.
MeasureResult run_measure(const MeasureOptions& options, const Progress& progress = {});

nlohmann::json to_json(const MeasureResult& result, const MeasureOptions& options);

// `aovar measure`: one scene's measurement with what the command adds around run_measure (sweep adds the
// same over all its scenes at once).
struct MeasureSceneOptions {
  MeasureOptions measure;
  bool prune_by_profile = true;   // drop, before compiling, what the scene's profile drops (prune_by_profile)
  trace::GpuEstimateOptions gpu;  // with families: the rows estimated on them, measure.json written again
};
// Checks the request (check_request, the GPU names) before profiling or measuring anything; throws as
// run_measure does.
MeasureResult measure_scene(const MeasureSceneOptions& options, const Progress& progress = {});

// Sets glibc's heap thresholds so freed driver buffers stay mapped (run_measure calls it; timing code
// outside run_measure should too). Process-wide and idempotent.
void keep_heap_mapped();

}  // namespace aovar::measure
