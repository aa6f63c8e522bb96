#pragma once
// A scene's profile as `aovar profile` and `aovar list --scene` compute it: the manifest and its whole
// variant space loaded once (the profile picks its flicker pair from that space, which is then pruned).
#include <string>

#include "cli/options.h"
#include "cli/render_options.h"
#include "profile/profile.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace aovar::cli {

struct ProfileArgs {
  profile::Options options;
  std::string size = default_size, out;
  bool no_flicker = false, no_cache = false;

  // The options with the manifest, --size, --no-flicker and --no-cache applied (the default compile cache).
  profile::Options resolve(const compile::ManifestSource& manifest) const;
};

struct SceneProfile {
  variants::Manifest manifest;
  variants::VariantSpace space;  // every variant after the rules (no --variants globs)
  profile::Profile profile;
};
// Profiles options.scene with a status line on the terminal.
SceneProfile run_scene_profile(const profile::Options& options);

}  // namespace aovar::cli
