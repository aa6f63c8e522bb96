#pragma once
// Option helpers shared by every subcommand, the generator's included (manifest, cache folder, variant
// selection, --shard, --json), the progress on stderr and the exception -> exit code rule. The options of the
// rendering subcommands are in cli/render_options.h (not built with AOVAR_WITH_RENDER=OFF).
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/exit_code.h"
#include "compile/generate.h"
#include "shard/env.h"
#include "util/out_lock.h"
#include "util/progress.h"

namespace aovar::cli {

inline constexpr const char* default_manifest = "shader_src/aovar.toml";
inline constexpr const char* default_size = "640x360";  // measure, sweep, reference, profile, list --scene
// Help text of --cache-dir, after what the folder holds: where it is when the option is not given.
inline constexpr const char* cache_dir_default_help = "(default: $AOVAR_CACHE_DIR or ~/.cache/aovar)";

// --json: one JSON document on stdout (with schema_version) instead of the text (list, select, diff).
void add_json(CLI::App* cmd, bool& json);

// The manifest used when none is given: shader_src/aovar.toml in the working folder (a checkout of aovar),
// else the one installed beside the tool (<prefix>/share/aovar/shader_src/aovar.toml), else the former
// (whose absence the loader then reports).
std::string default_manifest_path();
// --manifest,-m with its default (default_manifest_path()) shown in --help.
void add_manifest(CLI::App* cmd, std::string& manifest);
// --cache-dir: `holds` says what the folder holds ("compile cache", "reference cache root", ...).
void add_cache_dir(CLI::App* cmd, std::string& dir, const std::string& holds);
// The cache folder to use: empty with --no-cache, else --cache-dir, else compile::CompileCache::default_dir().
std::filesystem::path cache_dir(const std::string& option, bool no_cache);

// The lock of the output folder `folder` (util::OutputLock: a second run into it is refused, naming the
// lock), held until the returned pointer goes; null when `folder` is empty (a command writing no files).
// Every command that writes an output folder takes it before reading or writing anything there.
std::unique_ptr<util::OutputLock> lock_output(const std::filesystem::path& folder);
// The same for a command whose output is one file (calibrate, merge): the lock of the file's folder.
std::unique_ptr<util::OutputLock> lock_output_of_file(const std::filesystem::path& file);

// The options every subcommand that selects, compiles or renders variants shares: the one place they are
// declared. scope() turns them into the compile::RunScope the libraries take.
struct CommonOptions {
  std::string manifest = default_manifest;
  std::vector<std::string> globs;
  std::vector<std::string> targets;
  int jobs = 0;
  int threads = 2;  // --threads, where the subcommand renders (add_threads)
  bool werror = false;
  std::string cache_dir;
  bool no_cache = false;

  std::filesystem::path cache() const { return cli::cache_dir(cache_dir, no_cache); }
  // The run scope, made on the first call and the same object after it: the manifest is parsed once per
  // command however many libraries the command calls. Throws std::runtime_error for an unknown --targets.
  const compile::RunScope& scope() const;

 private:
  mutable std::optional<compile::RunScope> scope_;
};
// --manifest, --variants, --targets, --jobs, --werror, --cache-dir and --no-cache.
void add_common(CLI::App* cmd, CommonOptions& o);
// --threads: rendering threads (llvmpipe's LP_NUM_THREADS, Embree's).
void add_threads(CLI::App* cmd, CommonOptions& o);
// The scope with the --variants globs and --werror.
compile::CompileOptions compile_options(const CommonOptions& o);
// Prints the diagnostics to stderr; returns false (and says so) when anything failed.
bool report_diagnostics(const compile::CompiledSpace& c);

// --shard "k/n" or "auto" (the scheduler's environment, shard/env.h) -> the shard; empty: not sharded. For
// auto it says on stderr which convention it used, and touches Bazel's TEST_SHARD_STATUS_FILE.
// Throws std::runtime_error naming --shard.
shard::ShardSpec shard_option(const std::string& text);
inline constexpr const char* shard_help =
    "k/n: only the k-th of n shards of the work, balanced by cost (join with aovar merge); auto: k and n from "
    "the scheduler (AOVAR_SHARD_INDEX/TOTAL, GitLab CI_NODE_*, Slurm SLURM_ARRAY_TASK_*, Kubernetes "
    "JOB_COMPLETION_INDEX + AOVAR_SHARD_TOTAL, Bazel TEST_SHARD_*)";

// Runs work(progress) with progress on stderr (util::ProgressReporter: a status line on a terminal, else a
// line every few seconds): lines that start with "note: " stay, and a terminal's status line is cleared when
// the work ends or throws (so an error gets a line of its own).
template <class Work>
auto with_status(Work&& work) {
  auto status = util::ProgressReporter::for_stderr();
  std::function<void(const std::string&)> progress = [&status](const std::string& line) {
    if (line.rfind("note: ", 0) == 0) status.keep(line);
    else status.update(line);
  };
  struct Clear {
    util::ProgressReporter& status;
    ~Clear() { status.clear(); }
  } clear{status};
  return work(progress);
}

// A finite number of at least `min` (above it when `strict`): CLI::PositiveNumber and CLI::Range let NaN
// through (every comparison with it is false) and take "inf".
CLI::Validator finite_number(double min, bool strict);

// A command-line error as one line naming the command that was run ("aovar ship: --rays: '0' is not a whole
// number from 1 to 65536 (aovar ship --help lists the options)"); the command is the subcommand being parsed.
struct Command;
std::string usage_error_line(const std::vector<Command>& commands, const std::string& what);

// Runs a subcommand: a std::exception becomes its message on stderr and ExitCode::error; a message that
// starts with an option ("--size: ...") is prefixed "aovar <command>: ".
ExitCode run_guarded(const std::function<ExitCode()>& run, const std::string& command = "");

}  // namespace aovar::cli
