// aovar stress: numerical stability of every variant under extreme cameras, radii, geometry and formats;
// exit 1 when a shipped variant has NaN, Inf or out-of-range AO.
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "stress/stress.h"
#include "stress/text.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct StressArgs {
  CommonOptions common;
  stress::Options options;
  std::string size = "96x54", out, scene, eye, target, up = "0,1,0", shard;
  std::vector<std::string> case_names;
  float fov = 60, near_plane = 0.1f, far_plane = 100, radius = 0;
  bool list_cases = false, no_reuse = false, mediump_fp32 = false;
  CalibrationOption calibration;
};

// "x,y,z" -> vec3 (inf and nan are spelled as strtof reads them).
glm::vec3 parse_vec3(const std::string& text, const char* option) {
  float v[3];
  const char* p = text.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[i] = std::strtof(p, &end);
    if (end == p || (i < 2 && *end != ',') || (i == 2 && *end != '\0'))
      throw std::runtime_error(fmt::format("{}: expected x,y,z (e.g. 1,2.5,-3), got '{}'", option, text));
    p = end + 1;
  }
  return {v[0], v[1], v[2]};
}

// The cases to run: the custom one (--scene, --eye, --target), then the --case names; none: the defaults.
std::vector<stress::Case> selected_cases(const StressArgs& a) {
  std::vector<stress::Case> cases;
  if (!a.scene.empty() || !a.eye.empty() || !a.target.empty()) {
    if (a.scene.empty() || a.eye.empty() || a.target.empty())
      throw std::runtime_error("stress: a custom case needs --scene, --eye and --target (and optionally --up, --fov, --near, --far, --radius)");
    cases.push_back(stress::custom_case(a.scene, parse_vec3(a.eye, "--eye"), parse_vec3(a.target, "--target"), a.fov,
                                        a.near_plane, a.far_plane, a.radius, parse_vec3(a.up, "--up")));
  }
  if (a.case_names.empty()) return cases;
  auto all = stress::default_cases();
  for (const auto& name : a.case_names) {
    auto it = std::find_if(all.begin(), all.end(), [&](const stress::Case& c) { return c.name == name; });
    if (it == all.end()) {
      std::string names;
      for (const auto& c : all) names += (names.empty() ? "" : ", ") + c.name;
      throw std::runtime_error("stress: unknown --case '" + name + "' (cases: " + names + ")");
    }
    cases.push_back(*it);
  }
  return cases;
}

stress::Options stress_options(const StressArgs& a) {
  stress::Options o = a.options;
  o.scope = a.common.scope();
  o.globs = a.common.globs;
  o.size = parse_size(a.size);
  o.out = a.out;
  o.reuse = !a.no_reuse;
  o.mediump_fp16 = !a.mediump_fp32;
  table::CalibrationRef calibration;  // stress applies the values and records no source
  a.calibration.load(o.scope.manifest.get(), calibration);
  o.calibration = std::move(calibration.values);
  o.cases = selected_cases(a);
  o.shard = shard_option(a.shard);
  return o;
}

// Per-variant pass/fail over the stress cases; exit 1 when a shipped variant fails.
ExitCode run_stress(const StressArgs& a) {
  if (a.list_cases) {
    std::cout << stress::cases_text(stress::default_cases());
    return ExitCode::ok;
  }
  const auto o = stress_options(a);
  const auto lock = lock_output(o.out);
  auto r = with_status([&](const auto& progress) { return stress::run_stress(o, progress); });
  const auto cases = o.cases.empty() ? stress::default_cases() : o.cases;
  std::cout << stress::to_text(r, o, cases);
  if (!r.shard_balance.empty())
    std::cout << fmt::format("shard {}: {}; OUT/shard.json written\n", o.shard.label(), r.shard_balance);
  return r.shipped_failed > 0 ? ExitCode::check_failed : ExitCode::ok;
}

void add_custom_case(CLI::App* cmd, StressArgs& a) {
  cmd->add_option("--scene,-s", a.scene, "custom case: scene (with --eye, --target)");
  cmd->add_option("--eye", a.eye, "custom case: camera position x,y,z");
  cmd->add_option("--target", a.target, "custom case: point looked at x,y,z");
  cmd->add_option("--up", a.up, "custom case: up vector x,y,z")->capture_default_str();
  cmd->add_option("--fov", a.fov, "custom case: vertical field of view, degrees")->capture_default_str();
  cmd->add_option("--near", a.near_plane, "custom case: near plane")->capture_default_str();
  cmd->add_option("--far", a.far_plane, "custom case: far plane (inf allowed)")->capture_default_str();
  cmd->add_option("--radius", a.radius, "custom case: AO radius in scene units (0: the scene's)")->capture_default_str();
}

}  // namespace

Command add_stress(CLI::App& app) {
  auto [cmd, a] = subcommand<StressArgs>(
      app, "stress",
      "numerical stability: every variant under extreme cameras, radii, geometry "
      "and formats; exit 1 when a shipped variant has NaN, Inf or out-of-range AO");
  auto& so = a->options;
  add_common(cmd, a->common);
  add_backends(cmd, so.backends);
  cmd->add_option("--size", a->size, "output size WxH")->capture_default_str();
  add_threads(cmd, a->common);
  cmd->add_flag("--shipped", so.shipped_only, "only the variants the manifest's [ship] list names");
  cmd->add_option("--case", a->case_names, "only this default case (repeatable; --list-cases)");
  cmd->add_flag("--list-cases", a->list_cases, "print the default cases and exit");
  add_custom_case(cmd, *a);
  cmd->add_option("--pair-tolerance", so.pair_tolerance,
                  "mediump/highp and r16f/r32f: per-pixel difference beyond which a pixel counts as different")
      ->capture_default_str();
  cmd->add_option("--pair-share", so.pair_share, "share of differing pixels that fails the pair")->capture_default_str();
  add_calibration(cmd, a->calibration, calibration_help);
  cmd->add_flag("--no-reuse", a->no_reuse, "check everything again (default: reuse checks whose inputs match OUT/stress.json)");
  cmd->add_option("--out,-o", a->out, "output folder: stress.json, stress.md");
  cmd->add_option("--shard", a->shard, shard_help);
  cmd->add_flag("--mediump-fp32", a->mediump_fp32, "run mediump in fp32 on the Vulkan backend (default: real fp16, as mobile GPUs)");
  cmd->add_option("--renders-per-process", so.renders_per_process,
                  "variant x case renders per child process (the Vulkan driver keeps memory per render; 0: render in this process)")
      ->check(whole_number(0, 1000000))
      ->capture_default_str();
  return {cmd, runs(a, run_stress)};
}

}  // namespace aovar::cli
