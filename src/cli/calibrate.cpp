// aovar calibrate: fit each method's artistic parameters to ray-traced references of training views (the
// built-in scenes, or the user's own with --scene), report the error on held-out views, write a calibration file.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "calibrate/calibrate.h"
#include "calibrate/file.h"
#include "calibrate/text.h"
#include "cli/commands.h"
#include "cli/limits.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "reference/reference.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct CalibrateArgs {
  calibrate::CalibrateOptions options;
  std::string manifest = default_manifest, cache_dir, size = "320x180", mode = default_reference_mode, out, views_file;
  int threads = 2;
  std::vector<std::string> scenes, views, holdout_views;
};

ExitCode run_calibrate(const CalibrateArgs& a) {
  calibrate::CalibrateOptions o = a.options;
  o.scope.manifest = std::filesystem::path(a.manifest);
  o.scope.cache_dir = cache_dir(a.cache_dir, false);
  o.scope.threads = a.threads;
  o.size = parse_size(a.size);
  o.mode = reference::parse_mode(a.mode);
  if (o.budget.max_evaluations < 1) throw std::runtime_error("--evaluations must be at least 1");
  if (a.scenes.empty() && (!a.views.empty() || !a.holdout_views.empty() || !a.views_file.empty()))
    throw std::runtime_error("--view, --holdout-view and --views-file need --scene (the built-in default split is fixed)");
  if (!a.scenes.empty()) {
    o.views_file = a.views_file;
    o.views = calibrate::split_views(a.scenes, a.views_file, a.views, a.holdout_views);
  }
  const auto lock = lock_output_of_file(a.out);
  auto c = with_status([&](const auto& progress) { return calibrate::calibrate(o, progress); });
  calibrate::write_calibration(a.out, c);
  std::cout << calibrate::to_text(c, a.out);
  return ExitCode::ok;
}

}  // namespace

Command add_calibrate(CLI::App& app) {
  auto [cmd, a] = subcommand<CalibrateArgs>(app, "calibrate",
                                 "fit each method's artistic parameters to ray-traced references (training views), "
                                 "report the error on held-out views, write a calibration file");
  auto& cal = a->options;
  add_manifest(cmd, a->manifest);
  cmd->add_option("--algorithms", cal.algorithms, "algorithms to fit (comma-separated; default: all)")->delimiter(',');
  cmd->add_option("--variants", cal.variants,
                  "fit each variant matching this glob on its own (repeatable; default: one variant per algorithm "
                  "stands for all of its variants)");
  cmd->add_option("--scene,-s", a->scenes,
                  "scene to fit on (repeatable: several scenes fit one shared set; default: the four built-in scenes)");
  cmd->add_option("--view", a->views, "training view (repeatable; default: every view not held out)");
  cmd->add_option("--holdout-view", a->holdout_views,
                  "held-out view, reported but not fitted on (repeatable; default: the views not given to --view, "
                  "else every third view: background of the derived views)");
  cmd->add_option("--views-file", a->views_file, "views side file (TOML or JSON) for the scene(s)");
  cmd->add_option("--normals", cal.fit_normals,
                  "normals of the variant each method is fitted with: buffer (RGB8 where read) or depth")
      ->check(CLI::IsMember({"buffer", "depth"}))
      ->capture_default_str();
  cmd->add_option("--backend,-b", cal.backend, render::backend_list(", ", " or "))->check(registered_backend())->capture_default_str();
  cmd->add_option("--size", a->size, "render and reference size WxH")->capture_default_str();
  add_rays(cmd, cal.rays, "reference rays per pixel");
  cmd->add_option("--mode", a->mode, "reference mode: occlusion or obscurance")->capture_default_str();
  cmd->add_option("--evaluations", cal.budget.max_evaluations, "objective evaluations per fit (NLopt BOBYQA; COBYLA for one parameter)")
      ->check(whole_number(1, kMaxEvaluations))
      ->capture_default_str();
  cmd->add_option("--threads", a->threads, "LP_NUM_THREADS for llvmpipe")->check(whole_number(1, kMaxThreads))->capture_default_str();
  cmd->add_option("--fits-at-once", cal.fits_at_once,
                  "methods (or variants) fitted at once, each on its own device (default 0: one per core; the "
                  "result does not depend on it)")
      ->check(whole_number(0, kMaxThreads))
      ->capture_default_str();
  cmd->add_option("--out,-o", a->out, "calibration file to write (e.g. shader_src/calibration.json)")->required();
  add_cache_dir(cmd, a->cache_dir, "compile and reference cache");
  return {cmd, runs(a, run_calibrate)};
}

}  // namespace aovar::cli
