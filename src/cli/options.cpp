#include "cli/options.h"

#include "calibrate/file.h"
#include "variants/manifest.h"

#include <fmt/format.h>

#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "compile/cache.h"
#include "gpu/families.h"
#include "compile/text.h"

namespace aovar::cli {

void add_json(CLI::App* cmd, bool& json) {
  cmd->add_flag("--json", json, "print one JSON document (with schema_version) instead of the text");
}

void add_manifest(CLI::App* cmd, std::string& manifest) {
  cmd->add_option("--manifest,-m", manifest, "manifest file")->capture_default_str();
}

void add_cache_dir(CLI::App* cmd, std::string& dir, const std::string& holds) {
  cmd->add_option("--cache-dir", dir, holds + " " + cache_dir_default_help);
}

std::filesystem::path cache_dir(const std::string& option, bool no_cache) {
  if (no_cache) return {};
  return option.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(option);
}

void add_common(CLI::App* cmd, CommonOptions& o) {
  add_manifest(cmd, o.manifest);
  cmd->add_option("--variants", o.globs, "only variants whose key matches this glob (repeatable)");
  cmd->add_option("--targets", o.targets, "vulkan,gl45,gles30 (default: the manifest's)")->delimiter(',');
  cmd->add_option("--jobs,-j", o.jobs, "compile threads (default: cores)");
  cmd->add_flag("--werror", o.werror, "treat glslang warnings as errors");
  add_cache_dir(cmd, o.cache_dir, "compile cache");
  cmd->add_flag("--no-cache", o.no_cache, "compile everything, read and write no cache");
}

compile::CompileOptions compile_options(const CommonOptions& o) {
  compile::CompileOptions c;
  for (const auto& t : o.targets) {
    auto target = variants::parse_target(t);
    if (!target) throw std::runtime_error("--targets: unknown target '" + t + "' (use vulkan, gl45, gles30)");
    c.targets.push_back(*target);
  }
  c.jobs = o.jobs;
  c.werror = o.werror;
  c.globs = o.globs;
  c.cache_dir = o.cache();
  return c;
}

bool report_diagnostics(const compile::CompiledSpace& c) {
  for (const auto& d : c.diagnostics) std::cerr << d << "\n";
  if (c.ok()) return true;
  std::cerr << compile::failure_line(c);
  return false;
}

std::filesystem::path CalibrationOption::resolve(const std::string& manifest) const {
  if (none) return {};
  if (!file.empty()) return file;
  auto next_to = std::filesystem::path(manifest).parent_path() / "calibration.json";
  return std::filesystem::exists(next_to) ? next_to : std::filesystem::path();
}

std::filesystem::path CalibrationOption::load(const std::string& manifest,
                                              std::map<std::string, render::ParamOverrides>& values, std::string& file,
                                              std::string& hash) const {
  const auto path = resolve(manifest);
  if (path.empty()) return path;
  values = calibrate::load_calibration(path, variants::load_manifest(manifest));
  const auto source = calibrate::calibration_source(path);
  file = source.file, hash = source.hash;
  return path;
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
                                   "AMD GPU families (e.g. navi21,vangogh,polaris10): every row's variant compiled on "
                                   "RADV's null device and estimated (gpu.<family> columns; docs/gpu-cost.md)");
  cmd->add_option("--gpu-size", o.frame, "frame size the --gpu estimate is for")->capture_default_str()->needs(families);
}

void RepsOption::apply(measure::MeasureOptions& o) const {
  if (reps == "auto") {
    o.auto_reps = measure::AutoReps{ci_target_pct / 100, cap_s};
    return;  // o.reps: the least number of rounds (the fixed default)
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
  o.reps = n;
  o.auto_reps.reset();
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

std::pair<int, int> parse_shard(const std::string& text) {
  int k = 0, n = 0;
  char slash = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &k, &slash, &n) != 3 || slash != '/' || n < 1 || k < 1 || k > n)
    throw std::runtime_error("--shard: expected k/n with 1 <= k <= n (e.g. 2/4), got '" + text + "'");
  return {k - 1, n};
}

ExitCode run_guarded(const std::function<ExitCode()>& run) {
  try {
    return run();
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return ExitCode::error;
  }
}

}  // namespace aovar::cli
