#pragma once
// The guard against an accidental whole-space run (issue 38): `measure` and `sweep` without --variants
// select every variant the manifest keeps, which on the default manifest is a job of many hours. Above
// kMostUnselected variants they refuse in one line naming the count, the estimated time and --all.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "compile/run_scope.h"

namespace aovar::cli {

// The most variants a run without --variants may select: the default sweep (scripts/default_selection)
// selects 26, the default manifest keeps over 12,000; test and example manifests hold a few dozen.
inline constexpr std::size_t kMostUnselected = 100;
// What one variant costs on one view at 640x360 with --reps auto on a 2-core machine: bench/shards' run of
// the default sweep on Sponza (190.9 s for 25 variants on 3 views, bench/README.md).
inline constexpr double kSecondsPerVariantView = 2.5;

// --all: run every variant the manifest keeps even without --variants.
void add_all(CLI::App* cmd, bool& all);

// What the run will do, for the estimate: views and backends per variant, and the shard count.
struct RunShape {
  std::string command;  // "measure" or "sweep"
  std::size_t views_per_variant = 1;
  std::size_t shards = 1;
};

// Throws std::runtime_error (one line) when `globs` is empty, `all` is false and the manifest keeps more than
// kMostUnselected variants; otherwise does nothing (a manifest error is left to the run, which reports it).
void check_whole_space(const compile::ManifestSource& manifest, const std::vector<std::string>& globs, bool all,
                       const RunShape& shape);

}  // namespace aovar::cli
