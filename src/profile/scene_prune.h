#pragma once
// Scene-profile pruning inside `aovar measure` and `aovar sweep` (issue 8): before anything is compiled, the
// scene is profiled as the run will render it (src/profile: its views, the frame size, the AO radius) and
// the selected variants the profile drops are left out of the compile and the measurement, each with the
// decision that drops it and its evidence (the text `aovar list --scene S --pruned` prints).
// The profile is stored as OUT/profile.json (next to measure.json, atomically) with a hash of everything it
// depends on — the scene's content, each view's camera and path, size, radius, threads, the tolerances,
// the manifest's text and the expanded programs of the flicker pair — so a repeated run reads it back
// instead of tracing depth and rendering the flicker pair again.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "profile/profile.h"
#include "scene/scene.h"
#include "table/pruning_counts.h"

namespace aovar::profile {

struct ScenePruning {
  std::string scene;
  std::vector<std::string> kept;       // of the variants the globs given to prune_scene select, sorted
  std::vector<table::DroppedVariant> dropped;  // the others, sorted by key
  Profile profile;                     // what the decisions were taken on
  std::string profile_file;            // where the profile is stored (empty without an output folder)
  bool reused = false;                 // read back from profile_file (its inputs were unchanged)
  double seconds = 0;                  // profiling (or reading back) and pruning

  bool drops(const std::string& key) const;
  // Over the variants `globs` select among those covered (every covered one when empty): the scene, the
  // counts before and after, dropped per rule and every dropped one with its rule and reason. No times:
  // shards of one sweep write the same section.
  table::PruningCounts counts(const std::vector<std::string>& globs) const;
  nlohmann::json to_json(const std::vector<std::string>& globs) const { return table::to_json(counts(globs)); }
  // "builtin:far keeps 3 of 5 selected variants; drops 2 (depth_format r16f 2)"
  std::string summary(const std::vector<std::string>& globs) const;
};

struct PruneOptions {
  Options profile;                  // manifest, scene, size, radius, threads, cache dir, tolerances (views: set
                                    // from prune_scene's `views`)
  std::filesystem::path store_dir;  // where profile.json is stored and read back (empty: nowhere)
  bool reuse = true;                // read a stored profile back when its inputs match
};

// Profiles `scene` (loaded with its views side file) on `views` at o.profile.size and radius (0: the
// scene's), compiling the flicker pair with its cache dir; reads STORE/profile.json back instead when
// o.store_dir is set, o.reuse is on and its inputs match, and writes it otherwise. `globs`: the variants to
// cover (the run's --variants, and sweep's --predict; empty: every variant after the manifest's rules).
ScenePruning prune_scene(const PruneOptions& o, const scene::Scene& scene, const std::vector<const scene::View*>& views,
                         const std::vector<std::string>& globs, const Progress& progress = {});

}  // namespace aovar::profile
