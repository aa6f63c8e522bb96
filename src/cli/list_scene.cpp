// aovar list --scene: the variants a scene's profile keeps (profile::prune), --pruned with each reason.
#include <iostream>

#include "cli/render_parts.h"
#include "cli/scene_profile.h"
#include "profile/pruned_text.h"

namespace aovar::cli {

ExitCode run_list_scene(const ListArgs& a) {
  ProfileArgs args;
  args.options.scene = a.scene;
  args.size = a.size;
  const auto o = args.resolve(a.common.scope().manifest);
  const auto s = run_scene_profile(o);
  auto pruned = profile::prune(s.manifest, s.space, s.profile, a.common.globs);
  if (a.json) std::cout << profile::list_json(s.manifest, s.space, pruned, o.scene, a.show_pruned).dump(1) << "\n";
  else std::cout << profile::list_text(s.manifest, s.space, pruned, o.scene, a.show_pruned);
  return ExitCode::ok;
}

}  // namespace aovar::cli
