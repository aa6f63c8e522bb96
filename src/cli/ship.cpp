// aovar ship: from a scene to the variant to ship in one command (profile, fit, race, select on held-out views).
#include <algorithm>

#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/limits.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "ship/ship.h"

namespace aovar::cli {
namespace {

struct ShipArgs {
  CommonOptions common;
  ship::ShipOptions options;
  std::string size = default_size, fit_size = "320x180", out, views_file, shard;
  std::vector<std::string> join;
  GpuOption gpu;  // only --gpu-size and --gpu-window apply; the family is --target
};

ExitCode run_ship(const ShipArgs& a) {
  ship::ShipOptions o = a.options;
  o.scope = a.common.scope();
  o.globs = a.common.globs;
  o.size = parse_size(a.size);
  o.fit_size = parse_size(a.fit_size, "--fit-size");
  o.views_file = a.views_file;
  o.gpu_frame = a.gpu.frame_size();
  o.gpu_window = a.gpu.window;
  o.out = a.out;
  o.shard = shard_option(a.shard);
  o.join.assign(a.join.begin(), a.join.end());
  const auto lock = lock_output(o.out);
  auto r = with_status([&](const auto& progress) { return ship::run_ship(o, progress); });
  std::cout << ship::to_text(r, o);
  const bool chosen = !r.choices.empty() && std::all_of(r.choices.begin(), r.choices.end(),
                                                        [](const ship::ShipChoice& c) { return c.selection.ok; });
  return chosen || !r.shard.empty() ? ExitCode::ok : ExitCode::check_failed;
}

}  // namespace

Command add_ship(CLI::App& app) {
  auto [cmd, a] = subcommand<ShipArgs>(
      app, "ship",
      "from a scene to the variant to ship: profile, fit on the training views, "
      "race the pruned space, select on the held-out views");
  auto& so = a->options;
  add_common(cmd, a->common);
  cmd->add_option("--scene,-s", so.scene, scene_help("the scene"))->capture_default_str();
  cmd->add_option("--views-file", a->views_file, "views side file (TOML or JSON) for the scene");
  cmd->add_option("--holdout-view", so.holdout_views,
                  "held-out view the choice is made on (repeatable; default: every third view of the scene)");
  auto* target = cmd->add_option("--target", so.targets,
                                 "GPUs with an estimate (AMD families or GL chips; comma-separated or repeated): time is "
                                 "the traced estimate on each (one render per variant for the error); several: one "
                                 "search, a choice per GPU, one build line")
                     ->delimiter(',');
  cmd->add_option("--backend,-b", so.backend, "the measured backend (" + render::backend_list() + ")")->check(registered_backend())->capture_default_str()->excludes(target);
  auto* budget = cmd->add_option("--budget-ms", so.query.budget_ms, "lowest error with time <= this")->check(finite_number(0, true));
  auto* budget_of = cmd->add_option("--budget-of", so.query.budget_of, "a variant key: no slower than it (beyond the noise)")
                        ->excludes(budget);
  cmd->add_option("--max-error", so.query.max_error, "the fastest variant with error.rmse <= this")
      ->check(finite_number(0, false))
      ->excludes(budget)
      ->excludes(budget_of);
  cmd->add_option("--size", a->size, "output size WxH")->capture_default_str();
  cmd->add_option("--fit-size", a->fit_size, "calibration render size WxH")->capture_default_str();
  cmd->add_option("--evaluations", so.fit_evaluations, "objective evaluations per method fit")->check(whole_number(1, kMaxEvaluations))->capture_default_str();
  cmd->add_option("--race-reps", so.race_reps, "timed rounds of the first round of the race")->check(whole_number(6, kMaxRounds))->capture_default_str();
  cmd->add_option("--batch", so.batch,
                  "measured backends: pipelines prepared and timed together (the race retires within one; default 128 "
                  "at 640x360 or less, fewer for larger frames, at least 24)")
      ->check(whole_number(0, kMaxBatch));
  cmd->add_option("--race-margin", so.race_margin,
                  "measured backends: eliminate only when the slowdown's 95 % interval lies above this ratio")
      ->check(finite_range(1, 10, false, true))
      ->capture_default_str();
  cmd->add_option("--ci-target", so.final_reps.ci_target,
                  "the last round: rounds until each row's 95 % interval half-width is within this share")
      ->check(finite_range(0, 1, true))
      ->capture_default_str();
  cmd->add_option("--reps-cap-s", so.final_reps.cap_s, "the last round: seconds of timed frames per pipeline at most")
      ->check(finite_range(0, 1e6, true))
      ->capture_default_str();
  add_rays(cmd, so.rays, "reference rays per pixel");
  add_threads(cmd, a->common);
  cmd->add_option("--gpu-size", a->gpu.frame, "with --target: the frame the estimate is for")->capture_default_str();
  cmd->add_option("--gpu-window", a->gpu.window, "with --target: share of each draw traced (centred window)")
      ->check(finite_range(0.05, 1.0))
      ->capture_default_str();
  auto* shard = cmd->add_option("--shard", a->shard,
                                "k/n or auto: profile, fit and screen only the k-th of n shards of the candidates, "
                                "then stop (join the shards' folders with --join)");
  cmd->add_option("--join", a->join, "the folders of every `ship --shard` run of this search: take their fit and "
                                     "screens, then eliminate, race the survivors and select")
      ->excludes(shard);
  cmd->add_option("--out,-o", a->out, "output folder: cost_table.json, report.html, calibration.json, the rounds")->required();
  return {cmd, runs(a, run_ship)};
}

}  // namespace aovar::cli
