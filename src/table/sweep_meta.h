#pragma once
// A cost table's header (cost_table.json's "meta"): what `aovar sweep`, `ship` and `merge` recorded about how
// the rows were measured. Typed where aovar reads it back (report, markdown, select, generate, merge); a field
// is optional because tables written by hand, by tests or by older versions hold only some of it, and a table
// read and written again keeps exactly the keys it had. The sections that belong to modules above the row (the
// GPU estimate, the dominated pruning, ship's choices, the reps settings) are kept as the
// JSON those modules write: this foundation cannot name their types. Keys this version does not know are kept
// as read in `other`.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "table/model_fit.h"
#include "table/pruning_counts.h"
#include "variants/manifest.h"

namespace aovar::table {

// One scene the rows were measured on (meta.scenes[]).
struct MeasuredScene {
  std::string scene;    // as given to --scene
  std::string measure;  // its measure.json, relative to the table's folder
  std::string hash;     // the scene file's hash
  double radius = 0;    // the AO radius used, in scene units
  bool operator==(const MeasuredScene&) const = default;
};

// The calibration the parameters came from (meta.calibration): `file` says where, `hash` what (its bytes),
// and `values` the fitted values it holds, so that a table says what every row was scored with on its own
// (generate --from-table embeds them). Empty `file`: none, the manifest's defaults.
struct CalibrationRef {
  std::string file, hash;
  variants::CalibratedValues values;
  bool operator==(const CalibrationRef&) const = default;
};

// The variants a scene's profile dropped before compiling (meta.pruned[]; profile/scene_prune.h decides them).
struct PrunedByProfile {
  PruningCounts selection;            // over the swept globs
  std::string profile;                         // the profile.json it was decided from, relative to the table's folder
  std::optional<PruningCounts> predict;  // over --predict's globs
  bool operator==(const PrunedByProfile&) const = default;
};

struct SweepMeta {
  std::optional<std::string> tool;            // "aovar sweep"
  std::optional<std::string> manifest;        // the variant manifest, as given
  std::optional<std::string> manifest_hash;   // its hash: generate --from-table refuses another manifest
  std::optional<std::vector<MeasuredScene>> scenes;
  std::optional<std::vector<std::string>> backends;
  std::optional<std::string> size;            // "WxH"
  std::optional<int> reps;                    // timed rounds (the minimum with --reps auto)
  std::optional<int> rays;                    // reference rays per pixel
  std::optional<bool> calibrated;             // calibrated parameters, not the manifest's defaults
  // Present and empty: measured without a calibration file (written as null).
  std::optional<std::optional<CalibrationRef>> calibration;
  std::optional<std::string> shard;           // "k/n" of the run that wrote it
  std::optional<bool> profile_prune;          // the scenes' profiles pruned the space
  std::optional<std::vector<PrunedByProfile>> pruned;
  std::optional<std::vector<std::string>> merged_from;  // the tables `aovar merge` joined
  std::optional<int> shards;                  // inputs of a merge that had a shard manifest
  std::optional<std::vector<ModelFit>> cost_models;  // one per scene, view and backend
  std::optional<nlohmann::json> reps_auto;    // measure::reps_auto_json: null when --reps was a number
  // Sections written and read by the modules that own them (null: absent).
  nlohmann::json reps_reached;  // measure::RepsReached::to_json
  nlohmann::json prune;         // sweep's --prune-dominated report
  nlohmann::json gpu;           // trace::RowGpuResult::to_json (--gpu)
  nlohmann::json ship;          // every choice `aovar ship` made
  nlohmann::json other = nlohmann::json::object();  // keys this version does not know, as read

  bool operator==(const SweepMeta&) const = default;
};

// The file edge. from_json throws std::runtime_error naming the key whose value has the wrong type.
nlohmann::json to_json(const SweepMeta& meta);
SweepMeta sweep_meta_from_json(const nlohmann::json& meta);
nlohmann::json to_json(const PrunedByProfile& pruned);

}  // namespace aovar::table
