// aovar reference: ray-trace the ground-truth AO of scene views (Embree).
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/limits.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "reference/reference.h"
#include "reference/text.h"

namespace aovar::cli {
namespace {

struct ReferenceArgs {
  reference::RunOptions options;
  std::string size = default_size, mode = default_reference_mode, scene = default_scene, views_file, out, cache_dir;
  bool no_cache = false;
};

// Throws std::runtime_error naming the option at fault.
reference::RunOptions run_options(const ReferenceArgs& a) {
  reference::RunOptions o = a.options;
  o.scene = a.scene;
  o.views_file = a.views_file;
  o.out = a.out;
  o.reference.size = parse_size(a.size);
  try {
    o.reference.mode = reference::parse_mode(a.mode);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("--mode: ") + e.what());
  }
  if (o.reference.rays < 1) throw std::runtime_error(fmt::format("--rays {}: need at least 1 ray per pixel", o.reference.rays));
  if (o.reference.threads < 0) throw std::runtime_error("--threads must be 0 (all cores) or more");
  if (o.reference.frame < 0) throw std::runtime_error("--frame must be 0 or more");
  o.reference.cache_dir = cache_dir(a.cache_dir, a.no_cache);
  return o;
}

ExitCode run_reference(const ReferenceArgs& a) {
  const auto o = run_options(a);
  const auto lock = lock_output(o.out);
  auto terminal = util::ProgressReporter::for_stderr();
  auto status = [&terminal](const std::string& line, bool final) {
    if (final) terminal.keep(line);
    else terminal.update(line);
  };
  reference::RunResult r;
  try {
    r = reference::run_reference(o, status);
  } catch (...) {
    terminal.clear();  // the error goes on a line of its own, not after the status
    throw;
  }
  std::cout << reference::to_text(r, o.out);
  return ExitCode::ok;
}

}  // namespace

Command add_reference(CLI::App& app) {
  auto [cmd, a] = subcommand<ReferenceArgs>(app, "reference", "ray-trace the ground-truth AO of scene views (Embree)");
  auto& ro = a->options;
  cmd->add_option("--scene,-s", a->scene, scene_help("the scene"))
      ->capture_default_str();
  cmd->add_option("--views-file", a->views_file, "views side file (TOML or JSON) for the scene");
  cmd->add_option("--view", ro.views, "view name (repeatable; default: the scene's first view)");
  cmd->add_option("--radius", ro.radius,
                  "AO radius: world units (0.5) or a percentage of the bounding-box diagonal (1.5%); default: the scene's");
  add_rays(cmd, ro.reference.rays, "hemisphere rays per pixel");
  cmd->add_option("--mode", a->mode, "occlusion (hit or not) or obscurance (a hit at t occludes 1 - t/radius)")
      ->capture_default_str();
  cmd->add_option("--size", a->size, "output size WxH")->capture_default_str();
  cmd->add_option("--threads", ro.reference.threads, "tracing threads (0 = all cores)")->check(whole_number(0, kMaxThreads))->capture_default_str();
  cmd->add_option("--frame", ro.reference.frame, "camera-path frame of the view (0 = its first pose)")->capture_default_str();
  cmd->add_option("--out,-o", a->out, "output folder: <view>.pfm, <view>.stderr.pfm, <view>.png, reference.json")
      ->required();
  add_cache_dir(cmd, a->cache_dir, "reference cache root");
  cmd->add_flag("--no-cache", a->no_cache, "trace everything, read and write no cache");
  return {cmd, runs(a, run_reference)};
}

}  // namespace aovar::cli
