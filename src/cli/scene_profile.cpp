#include "cli/scene_profile.h"

#include "scene/scene.h"

namespace aovar::cli {

profile::Options ProfileArgs::resolve(const compile::ManifestSource& manifest) const {
  profile::Options o = options;
  o.scope.manifest = manifest;
  o.scope.cache_dir = cache_dir("", no_cache);
  o.size = parse_size(size);
  o.measure_flicker = !no_flicker;
  return o;
}

SceneProfile run_scene_profile(const profile::Options& o) {
  SceneProfile s;
  s.manifest = o.scope.manifest.get();
  s.space = variants::build_space(s.manifest);
  const auto sc = scene::load_scene(o.scene);
  s.profile = with_status(
      [&](const auto& progress) { return profile::profile_scene(o, sc, s.manifest, s.space, progress); });
  return s;
}

}  // namespace aovar::cli
