#pragma once
// A sharded `aovar stress` (docs/distributed.md): the cases are split over the shards, each case with its
// scaled copies (compare_scaled needs both) as one unit, balanced by cost (every case renders every
// selected variant, so a case costs about the same as another: a unit costs its number of cases). Splitting
// by case keeps every mediump / r16f variant with its highp / r32f partner. The shard's manifest
// (OUT/shard.json, shard/manifest.h) records the inputs and the checks done.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "shard/assign.h"
#include "stress/stress.h"

namespace aovar::stress {

struct StressShard {
  shard::Assignment assignment;
  std::vector<Case> cases;   // this shard's, in the order given
  nlohmann::json inputs;     // hashes by input
  std::string balance;       // shard::balance_line
};

StressShard plan_shard(const Options& options, const std::vector<Case>& all, const compile::CompiledSpace& compiled);

void write_shard_manifest(const Options& options, const StressShard& plan, int checks, bool complete, double wall_s);

}  // namespace aovar::stress
