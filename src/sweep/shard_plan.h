#pragma once
// A sharded sweep's plan (docs/distributed.md): the selected variants (--variants and --predict) grouped
// into units that must run together (identical programs; mediump / highp twins, which llvmpipe runs as the
// same code), each unit's predicted cost (the static cost, or an earlier table's times with
// --shard-times), the cost-balanced assignment (shard/assign.h), and the hashes of the inputs for the
// shard manifest. Every shard computes the same plan from the same inputs.
#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "shard/assign.h"
#include "sweep/sweep.h"

namespace aovar::sweep {

struct ShardPlan {
  std::vector<shard::Unit> units;
  shard::Assignment assignment;
  std::shared_ptr<const std::set<std::string>> keys;  // the variant keys of this shard's units
  std::string costs_from;                             // "static cost" or "times of FILE (N of M variants)"
  nlohmann::json inputs;                              // hashes by input, for the shard manifest
};

// Throws std::runtime_error (one line) for an unreadable --shard-times table or one that shares no variant.
ShardPlan plan_shards(const SweepOptions& options);

// The rows the sweep's table counts for the shard manifest are its own; this writes OUT/shard.json.
void write_sweep_manifest(const SweepOptions& options, const ShardPlan& plan, const std::vector<table::CostRow>& rows,
                          bool complete, double wall_s);

}  // namespace aovar::sweep
