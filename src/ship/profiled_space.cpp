#include "ship/profiled_space.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "profile/scene_prune.h"
#include "profile/profile.h"
#include "variants/space.h"

namespace aovar::ship {

namespace {

// The variants the globs select whose normals come from a buffer (rgb8, rg8, oct16): with a lean, normals
// derived from depth match the reference better (docs/calibration.md), so the search leaves these out.
std::set<std::string> buffered_normal_variants(const variants::Manifest& manifest, const std::vector<std::string>& globs) {
  const int axis = variants::index(variants::Axis::normals);
  std::set<std::string> keys;
  for (const auto& e : variants::build_space(manifest, globs).variants)
    if (e.point[axis] >= 0 && manifest.values[axis][e.point[axis]].text != "depth") keys.insert(e.key);
  return keys;
}

std::string lean_text(const profile::Profile& p) {
  std::string s;
  for (const auto& v : p.views)
    if (v.shading_normal_share_over_10deg >= 0)
      s += fmt::format("{}{} {:.0f}%", s.empty() ? "" : ", ", v.view, 100 * v.shading_normal_share_over_10deg);
  return s.empty() ? "not measured" : "buffered normals over 10 deg from their faces on " + s + " of the geometry";
}

}  // namespace

ProfiledSpace profile_space(const ShipOptions& o, const scene::Scene& sc, const std::vector<std::string>& views,
                            const variants::Manifest& manifest, ShipResult& res, const Progress& say) {
  profile::PruneOptions po;
  po.profile.scope = o.scope;
  po.profile.scene = o.scene;
  po.profile.size = o.size;
  po.store_dir = o.out / "profile";
  std::vector<const scene::View*> profiled;
  for (const auto& v : views) profiled.push_back(&sc.view(v));
  ProfiledSpace out{profile::prune_scene(po, sc, profiled, o.globs, say), {}};
  const profile::ScenePruning& pruning = out.pruning;
  for (const auto& d : pruning.dropped) out.skip.insert(d.variant);
  res.selected = int(pruning.kept.size() + pruning.dropped.size());
  res.pruned = int(pruning.dropped.size());
  res.lean = profile::buffered_normals_lean(pruning.profile);
  res.lean_text = lean_text(pruning.profile);
  res.fit_normals = res.lean ? "depth" : "buffer";
  if (res.lean)
    for (const auto& k : buffered_normal_variants(manifest, o.globs))
      if (std::binary_search(pruning.kept.begin(), pruning.kept.end(), k) && k != o.query.budget_of && out.skip.insert(k).second)
        ++res.lean_dropped;
  if (res.selected - int(out.skip.size()) < 1)
    throw std::runtime_error("ship: the profile of " + o.scene + " leaves no variant to search");
  return out;
}

}  // namespace aovar::ship
