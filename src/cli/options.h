#pragma once
// Option helpers shared by the subcommands: each default of the CLI is spelled here once (manifest, cache
// folder, calibration file, frame size), with the parsers of --size and --shard, the progress on
// stderr and the exception -> exit code rule.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cli/exit_code.h"
#include "compile/generate.h"
#include "measure/measure.h"
#include "render/frame.h"
#include "util/progress.h"

namespace aovar::cli {

inline constexpr const char* default_manifest = "shader_src/aovar.toml";
inline constexpr const char* default_size = "640x360";  // measure, sweep, reference, profile
inline constexpr const char* default_scene = "builtin:atrium";  // measure, reference
inline constexpr const char* default_reference_mode = "occlusion";  // measure, reference, calibrate
// Help text of --cache-dir, after what the folder holds: where it is when the option is not given.
inline constexpr const char* cache_dir_default_help = "(default: $AOVAR_CACHE_DIR or ~/.cache/aovar)";

// --json: one JSON document on stdout (with schema_version) instead of the text (list, select, diff).
void add_json(CLI::App* cmd, bool& json);

// --manifest,-m with its default shown in --help.
void add_manifest(CLI::App* cmd, std::string& manifest);
// --cache-dir: `holds` says what the folder holds ("compile cache", "reference cache root", ...).
void add_cache_dir(CLI::App* cmd, std::string& dir, const std::string& holds);
// The cache folder to use: empty with --no-cache, else --cache-dir, else compile::CompileCache::default_dir().
std::filesystem::path cache_dir(const std::string& option, bool no_cache);

// The options of the subcommands that select and compile variants (list, generate, measure, sweep, stress).
struct CommonOptions {
  std::string manifest = default_manifest;
  std::vector<std::string> globs;
  std::vector<std::string> targets;
  int jobs = 0;
  bool werror = false;
  std::string cache_dir;
  bool no_cache = false;

  std::filesystem::path cache() const { return cli::cache_dir(cache_dir, no_cache); }
};
void add_common(CLI::App* cmd, CommonOptions& o);
// Throws std::runtime_error for an unknown --targets name.
compile::CompileOptions compile_options(const CommonOptions& o);
// Prints the diagnostics to stderr; returns false (and says so) when anything failed.
bool report_diagnostics(const compile::CompiledSpace& c);

// --calibration FILE and --no-calibration. The calibration file of a manifest is calibration.json next to
// it: it applies, when it exists, unless another file (--calibration) or none (--no-calibration) is asked for.
struct CalibrationOption {
  std::string file;
  bool none = false;

  // The file that applies: empty with --no-calibration or when there is none.
  std::filesystem::path resolve(const std::string& manifest) const;
  // The values of resolve()'s file, checked against the manifest (calibrate::load_calibration), into
  // `values`, and what measure.json and the cost table record about it into file / hash. Returns the file.
  std::filesystem::path load(const std::string& manifest, std::map<std::string, render::ParamOverrides>& values,
                             std::string& file, std::string& hash) const;
};
void add_calibration(CLI::App* cmd, CalibrationOption& o, const std::string& help);
inline constexpr const char* calibration_help = "calibration file (default: calibration.json next to the manifest)";

// --gpu FAMILY[,FAMILY...] and --gpu-size WxH (measure, sweep): the AMD families to estimate every row's
// variant on (gpu/by_key.h) and the frame the estimate is for.
struct GpuOption {
  std::string families;
  std::string frame = "1920x1080";
  // The families (empty without --gpu) and the frame; throws std::runtime_error naming the option.
  std::vector<std::string> family_list() const;
  render::Extent frame_size() const;
};
void add_gpu(CLI::App* cmd, GpuOption& o);

// --reps N|auto, --ci-target PCT and --reps-cap-s S (measure, sweep; measure::AutoReps). `reps` is the
// subcommand's default: "10" for measure, "auto" for sweep.
struct RepsOption {
  std::string reps;
  double ci_target_pct = 2;
  double cap_s = 2;
  // Sets options.reps and options.auto_reps; throws std::runtime_error naming --reps.
  void apply(measure::MeasureOptions& options) const;
};
void add_reps(CLI::App* cmd, RepsOption& o);

// "WxH" (1 to 16384 each) -> extent; throws std::runtime_error naming --size.
render::Extent parse_size(const std::string& text);
// "k/n" (1 <= k <= n) -> 0-based shard index and count; throws std::runtime_error naming --shard.
std::pair<int, int> parse_shard(const std::string& text);

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

// Runs a subcommand: a std::exception becomes its message on stderr and ExitCode::error.
ExitCode run_guarded(const std::function<ExitCode()>& run);

}  // namespace aovar::cli
