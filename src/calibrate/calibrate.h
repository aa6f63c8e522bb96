#pragma once
// Calibration (docs/architecture.md, "Ground truth and error"): SSAO methods carry artistic parameters (intensity, contrast, bias, falloff...);
// before methods are compared, each method's parameters marked `fit = true` in the manifest are fitted to
// minimise the mean squared error against ray-traced references on training views, and the error before
// and after is reported on views not used for fitting (what XeGTAO's auto-tune does). The fitted values
// go to a calibration file that `aovar measure` (and later `sweep`) apply per algorithm.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "reference/reference.h"
#include "render/plan.h"

namespace aovar::calibrate {

struct ViewCase {
  std::string scene, view;  // "builtin:atrium", "overview"
};

struct CalibrateOptions {
  std::filesystem::path manifest = "shader_src/aovar.toml";
  std::vector<std::string> algorithms;  // empty: every algorithm of the manifest
  std::string backend = "lavapipe";
  render::Extent size{320, 180};
  int rays = 256;
  reference::Mode mode = reference::Mode::occlusion;
  std::vector<ViewCase> training;   // empty: overview and closeup of every built-in scene
  std::vector<ViewCase> validation; // empty: the background view of every built-in scene
  int max_evaluations = 60;         // objective evaluations per algorithm (each renders every training view)
  int threads = 2;                  // LP_NUM_THREADS
  std::filesystem::path compile_cache, reference_cache;  // empty: none
};

struct ViewError {
  std::string scene, view;
  bool training = false;
  double rmse_before = 0, rmse_after = 0;
};

struct AlgorithmFit {
  std::string algorithm;
  std::string variant;              // the variant rendered while fitting (its values apply to all variants)
  render::ParamOverrides defaults;  // "ao.<name>" -> manifest default, for the fitted parameters
  render::ParamOverrides fitted;    // "ao.<name>" -> fitted value
  std::vector<ViewError> views;
  int evaluations = 0;
  double train_rmse_before = 0, train_rmse_after = 0;  // mean over training views
  double validation_rmse_before = 0, validation_rmse_after = 0;
};

struct Calibration {
  std::string backend;
  render::Extent size;
  int rays = 0;
  reference::Mode mode = reference::Mode::occlusion;
  std::vector<AlgorithmFit> fits;
};

using Progress = std::function<void(const std::string&)>;

// Throws std::runtime_error with a one-line message (unknown algorithm, scene or view; no variant to fit).
Calibration calibrate(const CalibrateOptions& options, const Progress& progress = {});

// The calibration file (JSON, written atomically) and the per-algorithm values `aovar measure` applies.
void write_calibration(const std::filesystem::path& path, const Calibration& calibration);
// Throws std::runtime_error "<file>: error: ..." for an unreadable or malformed file.
std::map<std::string, render::ParamOverrides> load_calibration(const std::filesystem::path& path);

// Bounded Nelder-Mead over [0, 1]^d (callers map to parameter ranges): minimises f from `start`, at most
// `max_evaluations` calls, stops when the simplex is smaller than `tolerance`. Returns the best point.
std::vector<double> minimize(const std::function<double(const std::vector<double>&)>& f, std::vector<double> start,
                             int max_evaluations, double initial_step = 0.15, double tolerance = 1e-3,
                             int* evaluations = nullptr);

}  // namespace aovar::calibrate
