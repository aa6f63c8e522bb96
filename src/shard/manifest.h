#pragma once
// The shard manifest (OUT/shard.json): what a shard was run on (a hash of each input), which shard it is,
// what it was assigned and did, and whether it finished. Written incomplete when the shard starts and
// complete when it ends, so a killed shard is recognisable; `aovar merge` checks a set of them.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "shard/assign.h"
#include "shard/env.h"

namespace aovar::shard {

inline constexpr const char* kManifestFile = "shard.json";

struct ShardManifest {
  std::string tool;        // "sweep", "stress", "generate"
  std::string version;     // aovar's version string
  // Hashes of each input (manifest, templates, scenes, views, options, ...) by name; input_hash covers them all.
  nlohmann::json inputs = nlohmann::json::object();
  std::string input_hash;
  int index = 0, count = 1;  // 0-based
  std::string convention;    // ShardSpec::convention
  int units = 0;             // units assigned (variants with their identical ones, or case groups)
  nlohmann::json plan;       // Assignment::to_json(): every shard's predicted load
  int done = 0;              // rows (sweep), checks (stress) or variants (generate) this shard produced
  // Sweep: the rows its cost_table.json holds, pinned when it completes (hash_row_keys of their keys), so
  // merge refuses a table whose rows were removed or added since. Empty: not pinned (stress, generate).
  std::string rows_hash;
  bool complete = false;
  double wall_s = 0;         // of the run that completed it

  std::string label() const;  // "2/4"
  nlohmann::json to_json() const;
  static ShardManifest from_json(const nlohmann::json& j, const std::string& source);  // throws naming source
};

// What every tool's shard writes, from its plan: the identity, inputs, the assignment and this shard's units,
// with done = 0 and complete = false (the caller sets done, complete and wall_s as the run goes).
ShardManifest planned_manifest(const std::string& tool, const std::string& version, const nlohmann::json& inputs,
                               const Assignment& assignment, int index, const std::string& convention,
                               const std::string& costs_from);

// A row set's identity: the hash of its keys (table::CostRow::key), sorted, one a line.
std::string hash_row_keys(std::vector<std::string> keys);
// Throws std::runtime_error (one line naming the shard and its table) unless the table's rows are the ones the
// manifest pins: their count (done) and the hash of their keys. A complete sweep shard must pin them.
void check_pinned_rows(const std::string& name, const ShardManifest& m, const std::string& table,
                       const std::vector<std::string>& keys);

// inputs -> input_hash (a hash of the canonical JSON dump).
std::string hash_inputs(const nlohmann::json& inputs);

void write_manifest(const std::filesystem::path& out_dir, const ShardManifest& m);  // atomic
// Throws std::runtime_error "FILE: ..." when it is missing or malformed (a shard number that is not a
// whole number, such as 2.5, included: JSON readers would truncate it).
ShardManifest read_manifest(const std::filesystem::path& file);

// The manifests of one sharded run, each with the name to report it by: throws std::runtime_error (one line
// naming the shard) for a shard of other inputs, another tool or another count, a duplicated, an incomplete
// or a missing shard.
void check_shard_set(const std::vector<std::pair<std::string, ShardManifest>>& shards);

// "planned max/mean 1.04; measured wall max/mean 1.21 (12.0 s .. 14.5 s)" over a checked set.
std::string balance_summary(const std::vector<std::pair<std::string, ShardManifest>>& shards);

}  // namespace aovar::shard
