// aovar measure: render and time variants on a scene through lavapipe / OSMesa (measure.json with --out).
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "calibrate/calibrate.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "measure/measure.h"
#include "profile/scene_prune.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct MeasureArgs {
  CommonOptions common;
  measure::MeasureOptions options;
  std::string size = default_size, out, scene = default_scene, views_file, reference_mode = default_reference_mode;
  std::vector<std::string> params;
  bool no_prune = false;
  CalibrationOption calibration;
};

// "PASS.NAME=NUMBER" items -> overrides; throws std::runtime_error naming --param.
render::ParamOverrides parse_params(const std::vector<std::string>& items) {
  render::ParamOverrides out;
  for (const auto& item : items) {
    auto eq = item.find('=');
    std::size_t used = 0;
    double value = 0;
    try {
      if (eq != std::string::npos) value = std::stod(item.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (eq == std::string::npos || item.find('.') > eq || used == 0 || used != item.size() - eq - 1)
      throw std::runtime_error("--param: expected PASS.NAME=NUMBER such as ao.intensity=1.5, got '" + item + "'");
    out[item.substr(0, eq)] = value;
  }
  return out;
}

// The measured rows as a table: one line per variant, view and backend.
// (Formatting of a measure result: to move into src/measure with its rewrite.)
std::string measure_table(const measure::MeasureResult& r) {
  bool truth = std::any_of(r.rows.begin(), r.rows.end(), [](const auto& row) { return row.error.has_value(); });
  std::string s = fmt::format("{:<46} {:<9} {:<10} {:>8} {:>8} {:>8} {:>6} {}  {}\n", "variant", "backend", "view",
                              "min ms", "median", "p90", "rel", truth ? "  rmse    ssim" : "", "passes (min ms)");
  for (const auto& row : r.rows) {
    std::string passes;
    for (const auto& [name, st] : row.passes) passes += fmt::format("{} {:.2f}  ", name, st.min);
    std::string error = !truth ? "" : row.error ? fmt::format("{:>6.4f} {:>7.4f}", row.error->rmse, row.error->ssim)
                                                : fmt::format("{:>14}", "-");
    s += fmt::format("{:<46} {:<9} {:<10} {:>8.2f} {:>8.2f} {:>8.2f} {:>6.2f} {}  {}{}\n", row.variant, row.backend,
                     row.view, row.time_ms.min, row.time_ms.median, row.time_ms.p90, row.rel_time, error, passes,
                     row.is_baseline ? "(baseline)" : row.reused ? "(reused)" : "");
  }
  return s;
}

// The "# ..." lines after the table: devices, scene and counts, pruning, calibration, contact sheets.
// (Formatting of a measure result: to move into src/measure with its rewrite.)
std::string measure_notes(const measure::MeasureResult& r, const measure::MeasureOptions& o, const MeasureArgs& a,
                          const std::filesystem::path& cal_file) {
  std::string s;
  for (const auto& d : r.devices) s += fmt::format("# {}: {}, {}, {} threads\n", d.backend, d.device, d.api_version, d.threads);
  const std::string json = a.out.empty() ? "" : util::display_path(std::filesystem::path(a.out) / "measure.json");
  s += fmt::format("# scene {} ({} triangles), radius {:.3g}, {} at {}, {} reps after {} warm-up; {}; "
                   "{} rows ({} reused) in {:.1f} s{}\n",
                   r.scene, r.triangles, r.radius, o.baseline, a.size, o.reps, o.warmup, r.counts, r.rows.size(),
                   r.reused, r.wall_s, a.out.empty() ? "" : " -> " + json);
  if (r.pruning)
    s += fmt::format("# pruned by the scene's profile: {} ({}){}\n", r.pruning->summary(o.globs),
                     r.pruning->reused ? fmt::format("profile reused in {:.2f} s", r.pruning->seconds)
                                       : fmt::format("profiled in {:.1f} s", r.pruning->seconds),
                     a.out.empty() ? std::string()
                                   : "; each with its reason in " + json + " \"pruned\" (--no-prune measures them)");
  if (!o.calibration.empty())
    s += "# calibrated parameters: " + util::display_path(cal_file) + " (--no-calibration: the manifest's defaults)\n";
  for (const auto& sheet : r.contact_sheets)
    s += "# contact sheet: " + util::display_path(std::filesystem::path(a.out) / sheet) + "\n";
  return s;
}

int run_measure(const MeasureArgs& a) {
  measure::MeasureOptions o = a.options;
  o.scene = a.scene;
  o.views_file = a.views_file;
  o.prune_by_profile = !a.no_prune;
  o.manifest = a.common.manifest;
  o.reference_mode = reference::parse_mode(a.reference_mode);
  if (o.reference_rays < 1) throw std::runtime_error("--rays must be at least 1");
  o.reference_cache = a.common.cache();
  const auto cal_file = a.calibration.resolve(a.common.manifest);
  if (!cal_file.empty()) o.calibration = calibrate::load_calibration(cal_file);
  o.globs = a.common.globs;
  o.jobs = a.common.jobs;
  o.size = parse_size(a.size);
  if (o.radius < 0) throw std::runtime_error("--radius must be positive (world units; omit it for the scene's default)");
  if (o.warmup < 0) throw std::runtime_error("--warmup must be 0 or more");
  o.params = parse_params(a.params);
  o.out = a.out;
  o.cache_dir = a.common.cache();
  auto r = with_status([&](const auto& progress) { return measure::run_measure(o, progress); });
  std::cout << measure_table(r) << measure_notes(r, o, a, cal_file);
  return 0;
}

}  // namespace

Command add_measure(CLI::App& app) {
  auto a = std::make_shared<MeasureArgs>();
  auto& mo = a->options;
  auto* cmd = app.add_subcommand("measure", "render and time variants on a scene through lavapipe / OSMesa");
  add_common(cmd, a->common);
  cmd->add_option("--scene,-s", a->scene, "builtin:atrium|spheres|stairs|cornell or an .obj/.gltf/.glb file")
      ->capture_default_str();
  cmd->add_option("--views-file", a->views_file, "views side file (TOML or JSON) for the scene");
  cmd->add_option("--view", mo.views, "view name (repeatable; default: the scene's first view)");
  cmd->add_option("--backend,-b", mo.backends, "lavapipe, osmesa (repeatable or comma-separated)")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--size", a->size, "output size WxH")->capture_default_str();
  cmd->add_option("--reps", mo.reps, "timed rounds (min-of-N)")->capture_default_str();
  cmd->add_option("--warmup", mo.warmup, "discarded frames after the first (JIT) frame")->capture_default_str();
  cmd->add_option("--threads", mo.threads, "LP_NUM_THREADS for llvmpipe")->capture_default_str();
  cmd->add_option("--batch", mo.batch, "pipelines prepared and interleaved at once")->capture_default_str();
  cmd->add_option("--baseline", mo.baseline, "variant timed in every round (rel_time = 1)")->capture_default_str();
  cmd->add_option("--radius", mo.radius, "AO radius in world units (default: the scene's)");
  cmd->add_option("--param", a->params, "override a parameter of the variants that take it: PASS.NAME=VALUE (repeatable)");
  cmd->add_option("--out,-o", a->out, "output folder: measure.json and images/");
  cmd->add_flag("--camera-path", mo.camera_path,
                "frames walk each view's camera path (default: its first pose; the image is the last frame)");
  cmd->add_flag("!--no-images", mo.images, "write no PFM/PNG images");
  cmd->add_flag("!--no-reuse", mo.reuse, "measure everything again even when OUT/measure.json has the row");
  cmd->add_flag("--no-prune", a->no_prune,
                "measure every selected variant (default: drop, before compiling, those the scene's profile drops)");
  cmd->add_flag("--reference", mo.ground_truth,
                "score every row against a ray-traced reference of its view (error: rmse, mae, psnr, ssim, bias, max)");
  cmd->add_option("--rays", mo.reference_rays, "reference rays per pixel (with --reference)")->capture_default_str();
  cmd->add_option("--reference-mode", a->reference_mode, "occlusion or obscurance (with --reference)")
      ->capture_default_str();
  add_calibration(cmd, a->calibration,
                  "calibrated parameters per algorithm (default: calibration.json next to the manifest, when present)");
  return {cmd, [a] { return run_measure(*a); }};
}

}  // namespace aovar::cli
