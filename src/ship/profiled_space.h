#pragma once
// `aovar ship`'s first step: the profile of every view, what it prunes from the space, and the normals lean
// that decides the normal sources searched (with a lean, normals derived from depth only) and the fit's.
#include <set>
#include <string>
#include <vector>

#include "profile/scene_prune.h"
#include "scene/scene.h"
#include "ship/ship.h"
#include "variants/manifest.h"

namespace aovar::ship {

// What the search leaves out: the profile's drops and, with a normals lean, the buffered-normal variants (the
// budget's own excepted). The counts and the lean are recorded in `res`.
struct ProfiledSpace {
  profile::ScenePruning pruning;
  std::set<std::string> skip;
};

// Throws std::runtime_error when nothing is left to search.
ProfiledSpace profile_space(const ShipOptions& options, const scene::Scene& scene, const std::vector<std::string>& views,
                            const variants::Manifest& manifest, ShipResult& result, const Progress& say);

}  // namespace aovar::ship
