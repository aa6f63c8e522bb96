// aovar measure: render and time variants on a scene through the registered backends (measure.json with --out).
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/limits.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "cli/whole_space.h"
#include "measure/measure.h"
#include "measure/text.h"
#include "reference/reference.h"
#include "util/parse_number.h"

namespace aovar::cli {
namespace {

struct MeasureArgs {
  CommonOptions common;
  measure::MeasureOptions options;
  std::string size = default_size, out, scene = default_scene, views_file, reference_mode = default_reference_mode;
  std::vector<std::string> params;
  bool no_prune = false, all = false;
  CalibrationOption calibration;
  GpuOption gpu;
  RepsOption reps{"10"};
};

// "PASS.NAME=NUMBER" items -> overrides; throws std::runtime_error naming --param.
render::ParamOverrides parse_params(const std::vector<std::string>& items) {
  render::ParamOverrides out;
  for (const auto& item : items) {
    const auto eq = item.find('=');
    const auto value = eq == std::string::npos ? std::nullopt : util::whole_double(item.substr(eq + 1));
    if (!value || item.find('.') > eq)
      throw std::runtime_error("--param: expected PASS.NAME=NUMBER such as ao.intensity=1.5, got '" + item + "'");
    out[item.substr(0, eq)] = *value;
  }
  return out;
}

ExitCode run_measure(const MeasureArgs& a) {
  measure::MeasureSceneOptions request{.measure = a.options, .prune_by_profile = !a.no_prune, .gpu = a.gpu.options()};
  measure::MeasureOptions& o = request.measure;
  o.scope = a.common.scope();
  o.scene = a.scene;
  o.views_file = a.views_file;
  o.truth.mode = reference::parse_mode(a.reference_mode);
  if (o.truth.rays < 1) throw std::runtime_error("--rays must be at least 1");
  const auto cal_file = a.calibration.load(o.scope.manifest.get(), o.calibration);
  o.globs = a.common.globs;
  o.size = parse_size(a.size);
  a.reps.apply(o);
  if (o.radius < 0) throw std::runtime_error("--radius must be positive (world units; omit it for the scene's default)");
  if (o.timing.warmup < 0) throw std::runtime_error("--warmup must be 0 or more");
  o.params = parse_params(a.params);
  o.out = a.out;
  const std::size_t views = std::max<std::size_t>(o.views.size(), 1) * std::max<std::size_t>(o.backends.size(), 1);
  check_whole_space(o.scope.manifest, a.common.globs, a.all, {"measure", views, 1});
  const auto lock = lock_output(o.out);
  auto r = with_status([&](const auto& progress) { return measure::measure_scene(request, progress); });
  std::cout << measure::to_text(r) << measure::notes_text(r, o, cal_file);
  return ExitCode::ok;
}

}  // namespace

Command add_measure(CLI::App& app) {
  auto [cmd, a] = subcommand<MeasureArgs>(
      app, "measure",
      "render and time variants on a scene through " + render::backend_list(" / "));
  auto& mo = a->options;
  add_common(cmd, a->common);
  cmd->add_option("--scene,-s", a->scene, scene_help("the scene"))
      ->capture_default_str();
  cmd->add_option("--views-file", a->views_file, "views side file (TOML or JSON) for the scene");
  cmd->add_option("--view", mo.views, "view name (repeatable; default: the scene's first view)");
  add_backends(cmd, mo.backends);
  cmd->add_option("--size", a->size, "output size WxH")->capture_default_str();
  add_reps(cmd, a->reps);
  cmd->add_option("--warmup", mo.timing.warmup, "discarded frames after the first (JIT) frame")->check(whole_number(0, kMaxWarmup))->capture_default_str();
  add_threads(cmd, a->common);
  add_device(cmd, mo.device);
  cmd->add_option("--batch", mo.timing.batch, "pipelines prepared and interleaved at once")->check(whole_number(1, kMaxBatch))->capture_default_str();
  add_gpu(cmd, a->gpu);
  cmd->add_option("--baseline", mo.baseline, "variant timed in every round (rel_time = 1)")->capture_default_str();
  cmd->add_option("--radius", mo.radius, "AO radius in world units (default: the scene's)");
  cmd->add_option("--param", a->params, "override a parameter of the variants that take it: PASS.NAME=VALUE (repeatable)");
  cmd->add_option("--out,-o", a->out, "output folder: measure.json and images/");
  cmd->add_flag("--camera-path", mo.timing.camera_path,
                "frames walk each view's camera path (default: its first pose; the image is the last frame)");
  cmd->add_flag("!--no-images", mo.images, "write no PFM/PNG images");
  cmd->add_flag("!--own-gbuffers", mo.share_gbuffer,
                "every variant draws its own G-buffer (default: one per format, shared; the images are identical)");
  cmd->add_flag("!--no-reuse", mo.reuse, "measure everything again even when OUT/measure.json has the row");
  cmd->add_flag("--no-prune", a->no_prune,
                "measure every selected variant (default: drop, before compiling, those the scene's profile drops)");
  cmd->add_flag("--reference", mo.truth.enabled,
                "score every row against a ray-traced reference of its view (error: rmse, mae, psnr, ssim, bias, max)");
  add_rays(cmd, mo.truth.rays, "reference rays per pixel (with --reference)");
  cmd->add_option("--reference-mode", a->reference_mode, "occlusion or obscurance (with --reference)")
      ->capture_default_str();
  add_calibration(cmd, a->calibration,
                  "calibrated parameters per algorithm (default: calibration.json next to the manifest, when present)");
  add_all(cmd, a->all);
  return {cmd, runs(a, run_measure)};
}

}  // namespace aovar::cli
