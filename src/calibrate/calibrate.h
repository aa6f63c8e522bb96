#pragma once
// Calibration (docs/calibration.md): SSAO methods carry artistic parameters (intensity, contrast, bias,
// falloff...); each method's parameters marked `fit = true` in the manifest are fitted to minimise the
// mean squared error against ray-traced references on training views, and the error before and after is
// reported on held-out views (what XeGTAO's auto-tune does for its user's scene). Any scene can be used,
// several at once fit one shared set. The fitted values go to a calibration file that measure, sweep and
// stress apply per algorithm, or per variant for variants fitted on their own.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "calibrate/optimize.h"
#include "reference/reference.h"
#include "compile/run_scope.h"
#include "render/backend.h"
#include "render/plan.h"
#include "variants/manifest.h"

namespace aovar::calibrate {

struct ViewCase {
  std::string scene, view;  // "builtin:atrium", "overview"
  bool operator==(const ViewCase&) const = default;
};

// The views a calibration fits on and the ones it reports on.
struct ViewSplit {
  std::vector<ViewCase> training, holdout;
};

// The default calibration: overview and closeup of every built-in scene to fit on, their background views
// held out.
ViewSplit builtin_split();

// The split for user scenes: per scene, training = `training_views` when given, else every view not held
// out; held out = `holdout_views` when given, else (with training views given) the scene's other views,
// else every third view of the scene (the derived views: background). A views file replaces or adds
// views of every scene (with several scenes it must name views each of them accepts). Throws
// std::runtime_error with one line: an unknown view (naming the scene and its views), a view both trained
// and held out, no training or no held-out view left; it starts with `command` and names only its options.
ViewSplit split_views(const std::vector<std::string>& scenes, const std::filesystem::path& views_file,
                      const std::vector<std::string>& training_views, const std::vector<std::string>& holdout_views,
                      const std::string& command = "calibrate");

struct CalibrateOptions {
  compile::RunScope scope;  // the manifest, rendering threads, the cache root (compile and reference caches)
  std::vector<std::string> algorithms;  // empty: every algorithm of the manifest (with `variants` empty)
  // Variant globs: each matching variant is fitted on its own (a "variants" entry of the file) instead of
  // one variant standing for its method. Empty: one fit per algorithm.
  std::vector<std::string> variants;
  // The normals of the variant each method is fitted with (without `variants`): "buffer", the buffered RGB8
  // normal where the method reads one; "depth", normals derived from depth (the faces), for scenes whose
  // vertex normals lean from their faces (aovar profile measures it; docs/calibration.md).
  std::string fit_normals = "buffer";
  std::string backend = render::default_backend();
  render::Extent size{320, 180};
  int rays = 256;
  reference::Mode mode = reference::Mode::occlusion;
  ViewSplit views;                      // empty training: builtin_split()
  std::filesystem::path views_file;     // for loading the scenes of `views` (see split_views)
  Budget budget{100};                   // per fit; each evaluation renders every training view
  int fits_at_once = 0;                 // methods (or variants) fitted at once, each with its own runner; 0: cores
};

struct ViewError {
  std::string scene, view;
  bool training = false;
  double rmse_before = 0, rmse_after = 0;
};

// One fitted parameter set: of an algorithm (its `variant` stands for all of its variants) or of one variant.
struct Fit {
  std::string algorithm;
  std::string variant;              // the variant rendered while fitting
  bool per_variant = false;         // the values apply to `variant` only
  render::ParamOverrides defaults;  // "ao.<name>" -> manifest default, for the fitted parameters
  render::ParamOverrides fitted;    // "ao.<name>" -> fitted value
  std::vector<ViewError> views;
  Minimum search;                   // the optimiser's record: evaluations, stop reason, convergence curve
  int budget = 0;                   // evaluations it was allowed
  double train_rmse_before = 0, train_rmse_after = 0;  // mean over training views
  double holdout_rmse_before = 0, holdout_rmse_after = 0;
};

struct Calibration {
  std::string backend;
  render::Extent size;
  int rays = 0;
  reference::Mode mode = reference::Mode::occlusion;
  ViewSplit views;
  std::vector<Fit> fits;
};

using Progress = std::function<void(const std::string&)>;

// Throws std::runtime_error with a one-line message (unknown algorithm, scene or view; no variant to fit).
Calibration calibrate(const CalibrateOptions& options, const Progress& progress = {});

}  // namespace aovar::calibrate
