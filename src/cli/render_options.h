#pragma once
// Option helpers of the rendering subcommands (measure, sweep, calibrate, reference, profile, stress,
// analyze --gpu): each of their defaults is spelled here once (frame size, scene, reference mode,
// calibration file), with the parser of --size. Built only with AOVAR_WITH_RENDER (src/CMakeLists.txt).
#include <CLI/CLI.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli/limits.h"
#include "measure/measure.h"
#include "render/frame.h"
#include "trace/row_traffic.h"

namespace aovar::cli {

inline constexpr const char* default_scene = "builtin:atrium";  // measure, reference
inline constexpr const char* default_reference_mode = "occlusion";  // measure, reference, calibrate

// Help of --scene: `what` the scene is to this command, then the forms it takes, from the scene library (the
// built-in scenes, mesh files, the @scale= suffix), so that no subcommand lists the built-ins by hand.
std::string scene_help(const std::string& what);

// --calibration FILE and --no-calibration. The calibration file of a manifest is calibration.json next to
// it: it applies, when it exists, unless another file (--calibration) or none (--no-calibration) is asked for.
struct CalibrationOption {
  std::string file;
  bool none = false;

  // The file that applies: empty with --no-calibration or when there is none.
  std::filesystem::path resolve(const std::filesystem::path& manifest) const;
  // resolve()'s file, its hash and its values checked against the manifest (calibrate::read_calibration),
  // as measure.json and the cost table record them. Returns the file (empty: none).
  std::filesystem::path load(const variants::Manifest& manifest, table::CalibrationRef& calibration) const;
};
void add_calibration(CLI::App* cmd, CalibrationOption& o, const std::string& help);
inline constexpr const char* calibration_help = "calibration file (default: calibration.json next to the manifest)";

// --gpu FAMILY[,FAMILY...] and --gpu-size WxH (measure, sweep): the AMD families to estimate every row's
// variant on (gpu/by_key.h) and the frame the estimate is for.
struct GpuOption {
  std::string families;
  std::string frame = "1920x1080";
  bool trace = true;          // --gpu-trace on|off: the estimate on each row's traced view (issue 33)
  double window = 0.5;        // --gpu-window: share of each draw traced (trace::TraceOptions)
  // The families (empty without --gpu) and the frame; throws std::runtime_error naming the option.
  std::vector<std::string> family_list() const;
  render::Extent frame_size() const;
  trace::GpuEstimateOptions options() const;  // families, frame, trace, window
};
void add_gpu(CLI::App* cmd, GpuOption& o);

// --reps N|auto, --ci-target PCT and --reps-cap-s S (measure, sweep; measure::AutoReps). `reps` is the
// subcommand's default: "10" for measure, "auto" for sweep.
struct RepsOption {
  std::string reps;
  double ci_target_pct = 2;
  double cap_s = 2;
  // Sets options.timing.reps and options.timing.auto_reps; throws std::runtime_error naming --reps.
  void apply(measure::MeasureOptions& options) const;
};
void add_reps(CLI::App* cmd, RepsOption& o);

// --backend,-b: the backends to render on, repeatable or comma-separated (measure, sweep, stress); the list
// in the help is the registry's.
// A --backend value must name a registered backend: checked as it is parsed, so every command refuses an
// unknown name before it profiles or renders anything.
CLI::Validator registered_backend();
void add_backends(CLI::App* cmd, std::vector<std::string>& backends);
// --device: which device the Vulkan backend opens (measure, sweep).
void add_device(CLI::App* cmd, std::string& device);
// --rays: reference rays per pixel, from 1 to reference::kMaxRays; `help` says what they are for this command.
void add_rays(CLI::App* cmd, int& rays, const std::string& help);

// WxH with each side from 1 to kMaxSide and at most kMaxFramePixels pixels (cli/limits.h); throws
// std::runtime_error naming `option` ("--fit-size: ...", not --size).
render::Extent parse_size(const std::string& text, const std::string& option = "--size");

}  // namespace aovar::cli
