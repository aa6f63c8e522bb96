#include "cli/render_options.h"

#include <cstdio>
#include <stdexcept>

#include "calibrate/file.h"
#include "scene/scene.h"
#include "gpu/families.h"
#include "variants/manifest.h"

namespace aovar::cli {

std::filesystem::path CalibrationOption::resolve(const std::filesystem::path& manifest) const {
  if (none) return {};
  if (!file.empty()) return file;
  auto next_to = manifest.parent_path() / "calibration.json";
  return std::filesystem::exists(next_to) ? next_to : std::filesystem::path();
}

std::filesystem::path CalibrationOption::load(const variants::Manifest& manifest,
                                              std::map<std::string, render::ParamOverrides>& values,
                                              table::CalibrationRef& source) const {
  const auto path = resolve(manifest.path);
  if (path.empty()) return path;
  values = calibrate::load_calibration(path, manifest);
  source = calibrate::calibration_source(path);
  return path;
}

std::string scene_help(const std::string& what) {
  std::string builtins;
  for (const std::string& name : scene::builtin_scene_names()) builtins += (builtins.empty() ? "" : "|") + name;
  return what + ": " + builtins + ", or an .obj/.gltf/.glb file; SPEC" + std::string(scene::kScaleSuffix) +
         "F scales it";
}

void add_calibration(CLI::App* cmd, CalibrationOption& o, const std::string& help) {
  cmd->add_option("--calibration", o.file, help);
  cmd->add_flag("--no-calibration", o.none, "use the manifest's default parameters");
}

render::Extent parse_size(const std::string& text) {
  render::Extent e;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &e.width, &x, &e.height, &extra) != 3 || (x != 'x' && x != 'X') ||
      e.width < 1 || e.height < 1 || e.width > 16384 || e.height > 16384)
    throw std::runtime_error("--size: expected WxH such as 640x360 (1 to 16384 each), got '" + text + "'");
  return e;
}

std::vector<std::string> GpuOption::family_list() const {
  return families.empty() ? std::vector<std::string>{} : gpu::parse_families(families);
}

render::Extent GpuOption::frame_size() const {
  try {
    return parse_size(frame);
  } catch (const std::runtime_error&) {
    throw std::runtime_error("--gpu-size: expected WxH such as 1920x1080 (1 to 16384 each), got '" + frame + "'");
  }
}

void add_gpu(CLI::App* cmd, GpuOption& o) {
  auto* families = cmd->add_option("--gpu", o.families,
                                   "GPUs (AMD families such as navi21,vangogh; GL chips such as gf110,a320,t760,byt): "
                                   "every row's variant compiled for each and, for AMD families, estimated "
                                   "(gpu.<family> columns; docs/gpu-cost.md)");
  cmd->add_option("--gpu-size", o.frame, "frame size the --gpu estimate is for")->capture_default_str()->needs(families);
  cmd->add_option("--gpu-trace", o.trace,
                  "on: trace every row's texel fetches on its view through the Vulkan backend and estimate on each family's simulated "
                  "caches; off: the view-free roofline")
      ->transform(CLI::CheckedTransformer(std::map<std::string, bool>{{"on", true}, {"off", false}}))
      ->capture_default_str()->needs(families);
  cmd->add_option("--gpu-window", o.window, "share of each draw's width and height traced (a centred window)")
      ->check(CLI::Range(0.05, 1.0))->capture_default_str()->needs(families);
}

trace::GpuEstimateOptions GpuOption::options() const { return {family_list(), frame_size(), trace, window}; }

void RepsOption::apply(measure::MeasureOptions& o) const {
  if (reps == "auto") {
    o.timing.auto_reps = measure::AutoReps{ci_target_pct / 100, cap_s};
    return;  // o.timing.reps: the least number of rounds (the fixed default)
  }
  std::size_t used = 0;
  int n = 0;
  try {
    n = std::stoi(reps, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != reps.size() || n < 1)
    throw std::runtime_error("--reps: expected a number of rounds (1 or more) or auto, got '" + reps + "'");
  o.timing.reps = n;
  o.timing.auto_reps.reset();
}

void add_reps(CLI::App* cmd, RepsOption& o) {
  cmd->add_option("--reps", o.reps,
                  "timed rounds: N, or auto (until each row's 95 % interval is within --ci-target, at least 10 rounds)")
      ->capture_default_str();
  cmd->add_option("--ci-target", o.ci_target_pct,
                  "--reps auto: half-width of the 95 % interval of each row's ratio to the baseline, % of it")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--reps-cap-s", o.cap_s, "--reps auto: seconds of a row's own timed frames after which it stops anyway")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

}  // namespace aovar::cli
