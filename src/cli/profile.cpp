// aovar profile: what a scene needs, with evidence, and the variants it can drop; profile.json with --out.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/limits.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/scene_profile.h"
#include "cli/subcommand.h"
#include "profile/pruned_text.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct ProfileCommandArgs {
  ProfileArgs profile;
  std::string manifest = default_manifest;
};

ExitCode run_profile(const ProfileCommandArgs& a) {
  const auto lock = lock_output(a.profile.out);
  const auto o = a.profile.resolve(std::filesystem::path(a.manifest));
  const auto s = run_scene_profile(o);
  std::cout << profile::to_text(s.profile);
  auto pruned = profile::prune(s.manifest, s.space, s.profile);
  std::cout << profile::prune_line(s.space.variants.size(), pruned, o.scene);
  if (!a.profile.out.empty()) {
    auto j = profile::to_json(s.profile);
    j["kept"] = pruned.kept.size();
    j["dropped"] = pruned.dropped.size();
    util::write_atomic(std::filesystem::path(a.profile.out) / "profile.json", j.dump(1) + "\n");
  }
  return ExitCode::ok;
}

}  // namespace

Command add_profile(CLI::App& app) {
  auto [cmd, a] = subcommand<ProfileCommandArgs>(
      app, "profile",
      "what a scene needs (depth range, r16f error, radius in pixels, background, "
      "flicker, the renderer's buffers) and the variants it can drop");
  auto& p = a->profile;
  add_manifest(cmd, a->manifest);
  cmd->add_option("--scene,-s", p.options.scene, scene_help("the scene"))
      ->capture_default_str();
  cmd->add_option("--view", p.options.views, "only these views (repeatable; default: every view)");
  cmd->add_option("--size", p.size, "frame size the variants will run at")->capture_default_str();
  cmd->add_option("--radius", p.options.radius, "AO radius in scene units (0: the scene's)")->capture_default_str();
  cmd->add_option("--r16f-tolerance", p.options.r16f_tolerance,
                  "keep r16f while its p99 position error is under this share of the radius")->capture_default_str();
  cmd->add_option("--threads", p.options.scope.threads, "threads (Embree, the renderer)")->check(whole_number(1, kMaxThreads))->capture_default_str();
  cmd->add_flag("--no-flicker", p.no_flicker, "do not render the progressive pair along the camera paths");
  cmd->add_flag("--no-cache", p.no_cache, "compile the flicker pair without the cache");
  cmd->add_option("--out,-o", p.out, "folder for profile.json");
  return {cmd, runs(a, run_profile)};
}

}  // namespace aovar::cli
