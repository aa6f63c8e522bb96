#pragma once
// The schema version every JSON file and --json output of aovar carries ("schema_version"): a reader meeting
// a file from a newer aovar refuses it with one line instead of misreading fields whose meaning changed.
// Files written before the field existed have none and are read as version 1.
#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace aovar::util {

// Raise when a JSON output changes incompatibly (a field renamed, removed or with a new meaning).
// 2: a cost-table row's "gpu" object holds non-AMD chips and the vendor-neutral statistics (table/gpu_cost.h);
// analyze's gpu.json lists each distinct pipeline once. Version 1 files are read as before.
inline constexpr int kSchemaVersion = 2;

// A file this aovar must not read (nor overwrite): readers that treat a damaged file as absent (the reuse
// caches) let this one through.
struct NewerSchema : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws NewerSchema "FILE: error: schema_version N is newer than this aovar reads (M): ..." when
// `version` > kSchemaVersion, or when it is not a positive integer.
void check_schema_version(const nlohmann::json& version, const std::filesystem::path& file);

// Checks doc["schema_version"] when doc is an object that has one (older files have none: accepted).
template <class Json>
void check_schema(const Json& doc, const std::filesystem::path& file) {
  if (!doc.is_object()) return;
  const auto it = doc.find("schema_version");
  if (it != doc.end()) check_schema_version(nlohmann::json(*it), file);
}

}  // namespace aovar::util
