#pragma once
// `aovar sweep` (docs/cli.md): manifest x scenes x views -> measure with the ray-traced reference (and the
// calibration) -> one cost table (cost_table.json, .csv, .md) with the Pareto front of time against error.
// Resumable: each scene's measurements live in OUT/measure/<scene>/measure.json, rewritten atomically
// after every batch and reused row by row, so an interrupted sweep loses at most one batch and a re-run
// measures only what is missing (a repeat of a finished sweep measures and traces nothing).
// --shard k/n splits the variants over machines by cost (shard_plan.h) and writes OUT/shard.json;
// `aovar merge` checks the shards and joins them.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "measure/measure.h"
#include "shard/env.h"
#include "sweep/cost_models.h"
#include "table/table.h"
#include "trace/row_traffic.h"

namespace aovar::sweep {

struct SweepOptions {
  measure::MeasureOptions measure;   // manifest, globs, views (empty: every view of each scene), backends,
                                     // size, reps, rays, calibration, shard...; `scene` and `out` are set per scene
  std::vector<std::string> scenes = {"builtin:atrium"};
  std::filesystem::path out;
  // --gpu: every row's variant analysed and estimated on these AMD families, once over all scenes, after the
  // measurements (the estimate is no row input: it does not change the timing).
  trace::GpuEstimateOptions gpu;
  // Each scene's profile drops what it does not need before anything is compiled (profile/scene_prune.h,
  // over all views and the --variants and --predict selections); the CLI's default, off with --no-prune.
  bool prune_by_profile = false;
  // Variants (globs) to predict rather than measure: each one not measured gets a row per scene, view and
  // backend with the time of that group's predicting cost model, marked `predicted` (no error, not on the
  // front); a group whose models are all not predictive (min_model_spearman) fails the sweep instead.
  std::vector<std::string> predict;
  double min_model_spearman = kMinModelSpearman;  // --min-model-spearman: judge_model's least held-out ρ
  // --prune-dominated: measure a first share of the variants, then skip those the cost model predicts to be
  // dominated (the rule: measure_pruned in sweep.cpp); --prune-check N: of those, measure max(N, a tenth
  // rounded up) anyway and report how many would have reached the Pareto front.
  bool prune_dominated = false;
  int prune_check = 2;
  // Shard k of n (0-based k; n > 1): the variants are split by cost (shard_plan.h, which sets
  // measure.shard_keys), from the static cost or, with shard_times, an earlier cost_table.json's times.
  shard::ShardSpec shard;
  std::filesystem::path shard_times;
};

struct SweepResult {
  table::CostTable table;
  std::vector<ModelFit> cost_models;  // per scene, view and backend (meta.cost_models in the table's JSON)
  int rows_measured = 0, rows_reused = 0, rows_predicted = 0;
  int variants_skipped = 0, variants_checked = 0, checked_on_front = 0;  // --prune-dominated, over all scenes
  double profile_s = 0;     // scene profiles (prune_by_profile): profiling or reading back, and pruning
  int profiles_reused = 0;  // read back from OUT/measure/<scene>/profile.json
  double wall_s = 0;
  measure::RepsReached reps;  // over every scene's timed rows (meta.reps_reached)
  std::string shard_balance;  // sharded: this shard's share of the plan (shard::balance_line), else empty
};

// Throws std::runtime_error (and the scene/manifest/backend errors) with one-line messages.
SweepResult run_sweep(const SweepOptions& options, const std::function<void(const std::string&)>& progress = {});

// One scene's measurement and its rows alone (options.scenes holds one scene): no static costs, cost models,
// GPU costs, tables or reports. For ship's other training views (views in turn), which need each candidate's
// still error and nothing else, many times a run. Resumable as run_sweep (OUT/measure/<scene>/measure.json).
std::vector<table::CostRow> measure_rows(const SweepOptions& options, const std::function<void(const std::string&)>& progress = {});

// OUT/measure/<this> for a scene name: builtin:atrium -> builtin_atrium, a file -> its stem plus a short
// hash of the path (two sponza.obj in different folders stay apart).
std::string scene_folder(const std::string& scene);

}  // namespace aovar::sweep
