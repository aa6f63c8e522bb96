// `aovar sweep`: per scene a measurement (measure/), the static costs (static_costs.h), the cost models
// (cost_models.h), optional dominated-variant pruning (prune_dominated.h) and predicted rows, then one cost
// table and the reports.
#include "sweep/sweep.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "decide/pareto.h"
#include "gpu/by_key.h"
#include "profile/scene_prune.h"
#include "report/report.h"
#include "scene/scene.h"
#include "sweep/cost_models.h"
#include "sweep/prune_dominated.h"
#include "sweep/shard_plan.h"
#include "sweep/static_costs.h"
#include "util/clock.h"
#include "util/fs.h"
#include "util/hash.h"
#include "variants/manifest.h"

namespace aovar::sweep {
namespace fs = std::filesystem;
using json = nlohmann::json;

std::string scene_folder(const std::string& scene) {
  std::string out;
  if (scene.rfind("builtin:", 0) == 0) {
    out = "builtin_" + scene.substr(8);
  } else {
    out = fs::path(scene).stem().string() + "-" + util::hash_hex(scene).substr(0, 8);
  }
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return out;
}

namespace {

using Progress = std::function<void(const std::string&)>;

// Each scene's measure options and, with profile pruning, what its profile drops: every scene is profiled (or
// its stored profile read back) before anything is compiled. A variant is compiled when some scene keeps it,
// and measured (or predicted) on the scenes that keep it.
struct ScenePlans {
  std::vector<measure::MeasureOptions> per_scene;
  std::map<std::string, std::shared_ptr<const profile::ScenePruning>> pruning;  // by scene
  std::set<std::string> dropped_everywhere;
};

ScenePlans plan_scenes(const SweepOptions& o, SweepResult& res, const std::function<measure::Progress(std::size_t)>& say_for) {
  ScenePlans plans;
  std::vector<std::string> covered = o.measure.globs;  // what the pruning lists cover: --variants and --predict
  if (!covered.empty()) covered.insert(covered.end(), o.predict.begin(), o.predict.end());
  for (std::size_t i = 0; i < o.scenes.size(); ++i) {
    measure::MeasureOptions mo = o.measure;
    mo.scene = o.scenes[i];
    mo.truth.enabled = true;
    mo.out = o.out / "measure" / scene_folder(o.scenes[i]);
    if (mo.views.empty() || o.prune_by_profile) {
      scene::LoadOptions lo;
      lo.views_file = mo.views_file;
      const scene::Scene sc = scene::load_scene(mo.scene, lo);
      if (mo.views.empty())  // every view of the scene: the Pareto front per view and for the worst view
        for (const auto& v : sc.views) mo.views.push_back(v.name);
      if (o.prune_by_profile) {
        mo.pruning = measure::prune_by_profile(mo, sc, covered, say_for(i));
        plans.pruning[mo.scene] = mo.pruning;
        res.profile_s += mo.pruning->seconds;
        res.profiles_reused += mo.pruning->reused;
        std::set<std::string> dropped;
        for (const auto& d : mo.pruning->dropped) dropped.insert(d.variant);
        if (i == 0) plans.dropped_everywhere = std::move(dropped);
        else std::erase_if(plans.dropped_everywhere, [&](const std::string& k) { return !dropped.count(k); });
      }
    }
    plans.per_scene.push_back(std::move(mo));
  }
  return plans;
}

// Predicted rows: variants the --predict globs select that were not measured (nor share a measured variant's
// programs), timed by their group's predicting model; no error, never on the Pareto front. A group whose models
// are all not predictive refuses (predicting_model throws) rather than fill the table with guesses.
std::vector<table::CostRow> predicted_rows(const SweepOptions& o, const std::vector<table::CostRow>& measured_rows,
                                           const std::map<std::string, VariantStatic>& statics, const GroupModels& gm,
                                           const ScenePlans& plans) {
  std::set<std::string> measured, measured_programs;
  for (const auto& row : measured_rows) measured.insert(row.variant);
  for (const auto& key : measured) measured_programs.insert(statics.at(key).vulkan_programs);
  std::vector<table::CostRow> predicted;
  for (const auto& [key, vs] : static_costs(o.measure, o.predict, plans.dropped_everywhere)) {
    if (measured.count(key) || measured_programs.count(vs.vulkan_programs)) continue;
    if (!o.measure.in_shard(key)) continue;
    for (const auto& [g, grows] : gm.groups) {
      const table::CostRow& like = grows.front();  // scene, view, backend, size, threads
      if (auto p = plans.pruning.find(like.scene); p != plans.pruning.end() && p->second->drops(key)) continue;
      if (const decide::CostModel* model = predicting_model(gm, g))
        predicted.push_back(std::move(decide::predict_rows(*model, {unmeasured_row(like, key, vs)}).front()));
    }
  }
  return predicted;
}

// --gpu: every row's variant (measured or predicted) analysed on RADV's null device per family and
// estimated, once for all scenes: the estimate depends on the variant and the frame, not on the scene.
json add_gpu_costs(const SweepOptions& o, std::vector<table::CostRow>& rows, const Progress& progress) {
  std::vector<table::CostRow*> pointers;
  for (auto& r : rows) pointers.push_back(&r);
  return trace::add_gpu_costs(pointers, measure::gpu_request(o.measure, o.gpu), [&](const std::string& line) {
           if (progress) progress(line);
         }).to_json();
}

table::SweepMeta table_meta(const SweepOptions& o, const SweepResult& res, std::vector<table::MeasuredScene> scenes,
                            std::vector<table::ModelFit> models, std::vector<table::PrunedByProfile> profile_pruned,
                            const json& dominated) {
  table::SweepMeta m;
  m.tool = "aovar sweep";
  m.manifest = util::display_path(o.measure.scope.manifest.path());
  m.manifest_hash = o.measure.scope.manifest->hash;
  m.scenes = std::move(scenes);
  m.backends = o.measure.backends;
  m.size = fmt::format("{}x{}", o.measure.size.width, o.measure.size.height);
  m.reps = o.measure.timing.reps;
  m.reps_auto = measure::reps_auto_json(o.measure);
  m.reps_reached = res.reps.to_json();
  m.rays = o.measure.truth.rays;
  m.calibrated = !o.measure.calibration.values.empty();
  m.calibration = o.measure.calibration.file.empty() ? std::optional<table::CalibrationRef>() : o.measure.calibration;
  m.shard = o.shard.label();
  m.cost_models = std::move(models);
  m.profile_prune = o.prune_by_profile;
  if (o.prune_by_profile) m.pruned = std::move(profile_pruned);
  if (o.prune_dominated)
    m.prune = {{"skipped", res.variants_skipped}, {"checked", res.variants_checked},
               {"checked_on_front", res.checked_on_front}, {"scenes", dominated}};
  return m;
}

}  // namespace

SweepResult run_sweep(const SweepOptions& options, const Progress& progress) {
  auto start = std::chrono::steady_clock::now();
  if (options.out.empty()) throw std::runtime_error("sweep: --out is required");
  if (options.scenes.empty()) throw std::runtime_error("sweep: give at least one --scene");
  util::remove_stale_temps(options.out);  // what a killed earlier run was writing
  gpu::check_gpus(options.gpu.families);  // before anything is measured
  SweepResult res;
  SweepOptions o = options;  // a shard's plan chooses its variants
  std::optional<ShardPlan> shard_plan;
  if (o.shard.count < 1 || o.shard.index < 0 || o.shard.index >= o.shard.count)
    throw std::runtime_error(fmt::format("--shard {}/{}: use k/n with 1 <= k <= n", o.shard.index + 1, o.shard.count));
  if (o.shard.count > 1) {
    if (progress) progress("planning the shards: static cost of the selected variants");
    shard_plan = plan_shards(o);
    o.measure.shard_keys = shard_plan->keys;
    res.shard_balance = shard::balance_line(shard_plan->assignment, o.shard.index) + ", by " + shard_plan->costs_from;
    if (progress) progress(fmt::format("note: shard {}/{}: {}", o.shard.index + 1, o.shard.count, res.shard_balance));
    write_sweep_manifest(o, *shard_plan, {}, false, 0);  // incomplete until the table is written
  }
  json dominated = json::array();
  std::vector<table::MeasuredScene> scenes;
  std::vector<table::PrunedByProfile> profile_pruned;
  auto say_for = [&](std::size_t i) -> measure::Progress {
    return [&, where = fmt::format("scene {}/{} {}", i + 1, o.scenes.size(), o.scenes[i])](const std::string& line) {
      if (progress) progress(line.rfind("note: ", 0) == 0 ? line : where + ": " + line);
    };
  };
  const ScenePlans plans = plan_scenes(o, res, say_for);
  // With --prune-dominated the static costs come first: the cost model predicts from them what to skip.
  std::map<std::string, VariantStatic> statics;
  if (o.prune_dominated) {
    if (progress) progress("analysing the SPIR-V of the selected variants");
    statics = static_costs(o.measure, o.measure.globs, plans.dropped_everywhere);
  }
  for (std::size_t i = 0; i < o.scenes.size(); ++i) {
    const measure::MeasureOptions& mo = plans.per_scene[i];
    const std::string folder = scene_folder(o.scenes[i]);
    if (mo.pruning) {
      table::PrunedByProfile p{mo.pruning->counts(o.measure.globs),
                               (fs::path("measure") / folder / mo.pruning->profile_file).generic_string(), {}};
      if (!o.predict.empty()) p.predict = mo.pruning->counts(o.predict);
      profile_pruned.push_back(std::move(p));
    }
    DominatedPruning pruning;
    auto r = o.prune_dominated ? measure_pruned(o, mo, statics, folder, say_for(i), pruning) : measure::run_measure(mo, say_for(i));
    for (const auto& row : r.rows)  // the table's rows: not the baseline's timing-only one
      if (!row.is_baseline) ++(row.reused && !pruning.phase1_measured.count(row.inputs_hash) ? res.rows_reused : res.rows_measured);
    for (const auto& row : r.rows) res.reps.add(row);
    if (r.rows.empty()) continue;  // a shard holding none of the variants
    auto rows = measure::cost_rows(r, fs::path("measure") / folder);
    if (o.prune_dominated) {
      check_front(pruning, rows);
      res.variants_skipped += pruning.report["skipped"].get<int>();
      res.variants_checked += static_cast<int>(pruning.report["checked"].size());
      res.checked_on_front += static_cast<int>(pruning.report["checked_on_front"].size());
      dominated.push_back(pruning.report);
    }
    for (auto& row : rows) res.table.rows.push_back(std::move(row));
    scenes.push_back({o.scenes[i], (fs::path("measure") / folder / "measure.json").generic_string(), r.scene_hash, r.radius});
  }
  // Static cost of every row's variant, then a cost model per (scene, view, backend).
  std::set<std::string> keys;
  for (const auto& row : res.table.rows)
    if (!statics.count(row.variant)) keys.insert(row.variant);
  if (!keys.empty()) {
    if (progress) progress("analysing the SPIR-V of " + std::to_string(keys.size()) + " variants");
    statics.merge(static_costs(o.measure, std::vector<std::string>(keys.begin(), keys.end())));
  }
  for (auto& row : res.table.rows)
    if (auto it = statics.find(row.variant); it != statics.end()) row.static_cost = it->second.cost;
  auto gm = fit_group_models(res.table.rows, o.min_model_spearman);
  if (!o.predict.empty() && (!gm.best.empty() || !gm.unpredictable.empty())) {
    if (progress) progress("predicting the time of the unmeasured variants");
    auto predicted = predicted_rows(o, res.table.rows, statics, gm, plans);
    res.rows_predicted = static_cast<int>(predicted.size());
    for (auto& r : predicted) res.table.rows.push_back(std::move(r));
  }
  json gpu = o.gpu.families.empty() ? json(nullptr) : add_gpu_costs(o, res.table.rows, progress);
  decide::mark_pareto(res.table);
  res.cost_models = gm.models;
  res.table.meta = table_meta(o, res, std::move(scenes), gm.models, std::move(profile_pruned), dominated);
  res.table.meta.gpu = gpu;
  table::write_table_files(res.table, o.out);
  report::write_reports(res.table, o.out, o.measure.scope.manifest->algorithms);  // the charts' colours
  res.wall_s = util::seconds_since(start);
  if (shard_plan) write_sweep_manifest(o, *shard_plan, res.table.rows, true, res.wall_s);
  return res;
}

std::vector<table::CostRow> measure_rows(const SweepOptions& o, const Progress& progress) {
  if (o.scenes.size() != 1) throw std::logic_error("sweep::measure_rows: one scene");
  if (o.out.empty()) throw std::runtime_error("sweep: --out is required");
  util::remove_stale_temps(o.out);
  SweepResult res;
  const ScenePlans plans = plan_scenes(o, res, [&](std::size_t) -> measure::Progress { return progress; });
  const measure::MeasureResult r = measure::run_measure(plans.per_scene.front(), progress);
  return measure::cost_rows(r, fs::path("measure") / scene_folder(o.scenes.front()));
}

}  // namespace aovar::sweep
