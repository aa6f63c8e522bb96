#pragma once
// A sharded `aovar generate` (docs/distributed.md): the selected variants split over the shards by compile
// cost, each shard compiling and writing only its own (a shared --cache-dir then holds every program). A
// variant's cost is its share of the programs it needs: each program counts 1, split evenly among the
// selected variants that use it, so the shards' costs add up to the programs to compile. Every shard plans
// the same from the same manifest and templates.
#include <filesystem>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "shard/assign.h"

namespace aovar::compile {

struct GenerateShard {
  int index = 0, count = 1;
  std::string convention;
  shard::Assignment assignment;
  std::set<std::string> excluded;  // the other shards' variants (CompileOptions::exclude)
  nlohmann::json inputs;           // hashes by input
  std::string balance;             // shard::balance_line
};

// `planned`: plan_space of the whole selection (no compiling).
GenerateShard plan_generate_shard(const CompiledSpace& planned, const CompileOptions& options, int index, int count,
                                  const std::string& convention);

void write_generate_manifest(const std::filesystem::path& out, const GenerateShard& shard, int variants, bool complete,
                             double wall_s);

}  // namespace aovar::compile
