#pragma once
// Which shard this process is: `--shard k/n`, or `--shard auto` read from the environment the scheduler
// sets (docs/distributed.md). Pure functions over an environment map, so every convention is unit-tested
// without touching the process environment.
#include <map>
#include <string>

namespace aovar::shard {

using Env = std::map<std::string, std::string>;

// The most shards a run may have: far above any scheduler's array (GitHub's matrix stops at 256 jobs,
// Slurm's default MaxArraySize at 1,001), and refused before anything is planned per shard. A count above
// the units of work is refused too, by shard::assign.
inline constexpr int kMaxShards = 10000;

struct ShardSpec {
  int index = 0, count = 1;     // 0-based index of count shards
  std::string convention = "--shard";  // "--shard", "aovar", "GitLab CI", "Slurm array", "Kubernetes Indexed Job", "Bazel"
  std::string variables;        // the variables read, "NAME=value ...", for the line that says which was used
  std::string status_file;      // Bazel's TEST_SHARD_STATUS_FILE: the runner must touch it (empty: none)
  bool sharded() const { return count > 1; }
  std::string label() const;    // "2/4" (1-based)
  std::string describe() const; // "shard 2/4 from Slurm array (SLURM_ARRAY_TASK_ID=1 ...)"
};

// The conventions --shard auto reads, in this order (explicit first):
//   aovar:      AOVAR_SHARD_INDEX (0-based) and AOVAR_SHARD_TOTAL (a GitHub Actions matrix passes
//               strategy.job-index / strategy.job-total through them)
//   GitLab CI:  CI_NODE_INDEX (1-based) and CI_NODE_TOTAL (`parallel:`)
//   Slurm:      SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT, SLURM_ARRAY_TASK_MIN (and _STEP when set):
//               index = (ID - MIN) / STEP
//   Kubernetes: JOB_COMPLETION_INDEX (0-based) with AOVAR_SHARD_TOTAL (the Job's completions; Kubernetes
//               does not export it)
//   Bazel:      TEST_SHARD_INDEX (0-based), TEST_TOTAL_SHARDS, TEST_SHARD_STATUS_FILE
// Throws std::runtime_error (one line) when none is set, when one is set only in part or out of range, or
// when two give different shards; several that agree are fine (the first is reported).
ShardSpec shard_from_env(const Env& env);

// "--shard" as given: "auto" (shard_from_env) or "k/n"; empty: not sharded.
ShardSpec parse_shard_option(const std::string& text, const Env& env);

// The process environment as an Env (only the variables the conventions read).
Env process_env();

// Bazel's contract: a test runner that shards creates (touches) TEST_SHARD_STATUS_FILE. No-op when empty.
void touch_status_file(const ShardSpec& spec);

}  // namespace aovar::shard
