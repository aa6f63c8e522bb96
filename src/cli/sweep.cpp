// aovar sweep: measure variants on scenes against the ray-traced reference -> cost_table.{json,csv,md}.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <tuple>

#include "cli/commands.h"
#include "cli/limits.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "cli/whole_space.h"
#include "sweep/sweep.h"
#include "sweep/text.h"
#include "table/table.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct SweepArgs {
  CommonOptions common;
  sweep::SweepOptions options;
  std::string size = default_size, out, shard;
  bool no_prune = false, all = false;
  CalibrationOption calibration;
  GpuOption gpu;
  RepsOption reps{"auto"};  // the sweep's default: each row timed until its interval is narrow
};

ExitCode run_sweep(const SweepArgs& a) {
  sweep::SweepOptions o = a.options;
  o.out = a.out;
  measure::MeasureOptions& m = o.measure;
  o.prune_by_profile = !a.no_prune;
  m.scope = a.common.scope();
  m.globs = a.common.globs;
  m.size = parse_size(a.size);
  a.reps.apply(m);
  o.shard = shard_option(a.shard);
  const shard::ShardSpec& shard = o.shard;
  if (m.truth.rays < 1) throw std::runtime_error("--rays must be at least 1");
  o.gpu = a.gpu.options();
  const auto cal_file = a.calibration.load(m.scope.manifest.get(), m.calibration);
  // Every view of each scene: 3 for the built-in scenes and the derived views of a mesh.
  const std::size_t views = (m.views.empty() ? 3 : m.views.size()) * std::max<std::size_t>(o.scenes.size(), 1);
  check_whole_space(m.scope.manifest, a.common.globs, a.all,
                    {"sweep", views * std::max<std::size_t>(m.backends.size(), 1),
                     static_cast<std::size_t>(std::max(shard.count, 1))});
  const auto lock = lock_output(o.out);
  auto r = with_status([&](const auto& progress) { return sweep::run_sweep(o, progress); });
  std::cout << table::to_markdown(r.table) << sweep::notes_text(r, o, cal_file);
  if (!r.shard_balance.empty())
    std::cout << fmt::format("# shard {}: {}; OUT/shard.json written\n", shard.label(), r.shard_balance);
  return ExitCode::ok;
}

}  // namespace

Command add_sweep(CLI::App& app) {
  auto [cmd, a] = subcommand<SweepArgs>(
      app, "sweep",
      "measure variants on scenes against the ray-traced reference: cost_table.{json,csv,md}");
  auto& so = a->options;
  add_common(cmd, a->common);
  cmd->add_option("--scene,-s", so.scenes, scene_help("scenes (repeatable)"))
      ->capture_default_str();
  cmd->add_option("--view", so.measure.views, "view name (repeatable; default: every view of each scene)");
  add_backends(cmd, so.measure.backends);
  cmd->add_option("--size", a->size, "output size WxH")->capture_default_str();
  add_reps(cmd, a->reps);
  add_threads(cmd, a->common);
  add_device(cmd, so.measure.device);
  add_rays(cmd, so.measure.truth.rays, "reference rays per pixel");
  cmd->add_option("--batch", so.measure.timing.batch, "pipelines prepared and interleaved at once (rows are saved per batch)")
      ->check(whole_number(1, kMaxBatch))
      ->capture_default_str();
  cmd->add_option("--predict", so.predict,
                  "variants (globs, repeatable) to predict from the cost model instead of measuring: rows marked predicted");
  cmd->add_option("--min-model-spearman", so.min_model_spearman,
                  "least held-out Spearman of a cost model that may predict (--predict, --prune-dominated)")
      ->check(finite_range(-1.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--shard", a->shard, shard_help);
  cmd->add_option("--shard-times", so.shard_times,
                  "with --shard: balance the shards by the times of this earlier cost_table.json (default: static cost)");
  add_calibration(cmd, a->calibration, calibration_help);
  cmd->add_option("--views-file", so.measure.views_file, "views side file (TOML or JSON) for the scene(s)");
  cmd->add_option("--warmup", so.measure.timing.warmup, "discarded frames after the first (JIT) frame")
      ->check(whole_number(0, kMaxWarmup))
      ->capture_default_str();
  add_gpu(cmd, a->gpu);
  cmd->add_flag("--prune-dominated", so.prune_dominated,
                "measure a first share, then skip the variants the cost model predicts to be dominated");
  cmd->add_option("--prune-check", so.prune_check,
                  "with --prune-dominated: measure max(N, a tenth) of the skipped ones anyway, report if any reach the front")
      ->check(whole_number(0, 1000000))
      ->capture_default_str();
  cmd->add_flag("--no-prune", a->no_prune,
                "measure every selected variant on every scene (default: drop, before compiling, what each scene's "
                "profile drops)");
  cmd->add_flag("!--own-gbuffers", so.measure.share_gbuffer,
                "every variant draws its own G-buffer (default: one per format, shared; the images are identical)");
  add_all(cmd, a->all);
  cmd->add_option("--out,-o", a->out, "output folder: cost_table.{json,csv,md}, measure/<scene>/")->required();
  return {cmd, runs(a, run_sweep)};
}

}  // namespace aovar::cli
