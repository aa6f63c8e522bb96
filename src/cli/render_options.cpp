#include "cli/render_options.h"

#include <charconv>
#include <stdexcept>

#include <fmt/format.h>

#include "calibrate/file.h"
#include "scene/scene.h"
#include "gpu/families.h"
#include "reference/reference.h"
#include "render/backend.h"
#include "util/parse_number.h"
#include "variants/manifest.h"

namespace aovar::cli {

std::filesystem::path CalibrationOption::resolve(const std::filesystem::path& manifest) const {
  if (none) return {};
  if (!file.empty()) return file;
  auto next_to = manifest.parent_path() / "calibration.json";
  return std::filesystem::exists(next_to) ? next_to : std::filesystem::path();
}

std::filesystem::path CalibrationOption::load(const variants::Manifest& manifest, table::CalibrationRef& calibration) const {
  const auto path = resolve(manifest.path);
  calibration = calibrate::read_calibration(path, manifest);
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

render::Extent parse_size(const std::string& text, const std::string& option) {
  render::Extent e;
  const auto x = text.find_first_of("xX");
  auto whole = [](std::string_view s, int& out) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size() && !s.empty();
  };
  const bool parsed = x != std::string::npos && whole(std::string_view(text).substr(0, x), e.width) &&
                      whole(std::string_view(text).substr(x + 1), e.height);
  if (!parsed || e.width < 1 || e.height < 1 || e.width > kMaxSide || e.height > kMaxSide ||
      static_cast<long long>(e.width) * e.height > kMaxFramePixels)
    throw std::runtime_error(fmt::format("{}: expected WxH such as 640x360 (1 to {} each, at most 7680x4320 pixels), "
                                         "got '{}'",
                                         option, kMaxSide, text));
  return e;
}

std::vector<std::string> GpuOption::family_list() const {
  return families.empty() ? std::vector<std::string>{} : gpu::parse_families(families);
}

render::Extent GpuOption::frame_size() const { return parse_size(frame, "--gpu-size"); }

void add_gpu(CLI::App* cmd, GpuOption& o) {
  auto* families = cmd->add_option("--gpu", o.families,
                                   "GPUs (AMD families such as navi21,vangogh; GL chips such as gf110,a320,t760,byt): "
                                   "every row's variant compiled for each and estimated "
                                   "(gpu.<family> columns; docs/gpu-cost.md)");
  cmd->add_option("--gpu-size", o.frame, "frame size the --gpu estimate is for")->capture_default_str()->needs(families);
  cmd->add_option("--gpu-trace", o.trace,
                  "on: trace every row's texel fetches on its view through the Vulkan backend and estimate on each family's simulated "
                  "caches; off: the view-free roofline")
      ->transform(CLI::CheckedTransformer(std::map<std::string, bool>{{"on", true}, {"off", false}}))
      ->capture_default_str()->needs(families);
  cmd->add_option("--gpu-window", o.window, "share of each draw's width and height traced (a centred window)")
      ->check(finite_range(0.05, 1.0))->capture_default_str()->needs(families);
}

trace::GpuEstimateOptions GpuOption::options() const { return {family_list(), frame_size(), trace, window}; }

void RepsOption::apply(measure::MeasureOptions& o) const {
  if (reps == "auto") {
    o.timing.auto_reps = measure::AutoReps{ci_target_pct / 100, cap_s};
    return;  // o.timing.reps: the least number of rounds (the fixed default)
  }
  const auto n = util::whole_int(reps);
  if (!n || *n < 1 || *n > kMaxRounds)
    throw std::runtime_error(fmt::format("--reps: expected a number of rounds (1 to {}) or auto, got '{}'", kMaxRounds, reps));
  o.timing.reps = *n;
  o.timing.auto_reps.reset();
}

CLI::Validator registered_backend() {
  return CLI::Validator(
      [](std::string& name) -> std::string {
        try {
          (void)render::backend_info(name);
          return "";
        } catch (const render::BackendError& e) {
          return e.what();
        }
      },
      "NAME");
}

void add_backends(CLI::App* cmd, std::vector<std::string>& backends) {
  cmd->add_option("--backend,-b", backends, render::backend_list() + " (repeatable or comma-separated)")
      ->delimiter(',')->check(registered_backend())->capture_default_str();
}

void add_device(CLI::App* cmd, std::string& device) {
  cmd->add_option("--device", device, "the Vulkan backend: device by name substring or index (default: the CPU device)");
}

void add_rays(CLI::App* cmd, int& rays, const std::string& help) {
  cmd->add_option("--rays", rays, help)->check(whole_number(1, reference::kMaxRays))->capture_default_str();
}

void add_reps(CLI::App* cmd, RepsOption& o) {
  cmd->add_option("--reps", o.reps,
                  "timed rounds: N, or auto (until each row's 95 % interval is within --ci-target, at least 10 rounds)")
      ->capture_default_str();
  cmd->add_option("--ci-target", o.ci_target_pct,
                  "--reps auto: half-width of the 95 % interval of each row's ratio to the baseline, % of it")
      ->check(finite_range(0, 100, true))
      ->capture_default_str();
  cmd->add_option("--reps-cap-s", o.cap_s, "--reps auto: seconds of a row's own timed frames after which it stops anyway")
      ->check(finite_range(0, 1e6, true))
      ->capture_default_str();
}

}  // namespace aovar::cli
