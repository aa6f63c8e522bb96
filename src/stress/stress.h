#pragma once
// `aovar stress` (issue 7): renders every selected variant through the real pipeline under configurations
// that provoke the numerical failures users report — extreme near/far planes and an infinite far plane,
// a camera grazing a plane, radii from 1e-4 to 1e4 scene units, geometry at the screen edges, frames of
// nothing but sky, normals at every angle (RG decoding), degenerate geometry, far depth in r16f — reads
// the AO result back as floats and counts NaN, Inf and values outside [0, 1]. Variants that differ only in
// precision (mediump / highp) or depth format (r16f / r32f) are compared pixel by pixel on every case.
// Before the variants, each case is probed once per backend: the G-buffer's linear depth must cover the
// pixels a ray tracer (Embree) sees geometry at, within `coverage` — a camera the renderer cannot express
// (NaN matrices, depth beyond the clear value) loses the geometry and would otherwise read as open sky; a
// probe failure fails every variant on that case. Each check also reports its RMSE against the ray-traced
// reference (informational: methods differ too much for one threshold).
// A variant fails when any case gives a non-finite or out-of-range pixel on any backend, or when its
// mediump / r16f image departs from its highp / r32f partner on more than `pair_share` of the pixels by
// more than `pair_tolerance`. Each failure comes with the `aovar stress` command that reproduces it.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/health.h"
#include "compile/run_scope.h"
#include "shard/env.h"
#include "render/frame.h"
#include "render/backend.h"
#include "render/plan.h"
#include "scene/scene.h"

namespace aovar::stress {

// One configuration: a scene, an explicit camera and an AO radius.
struct Case {
  std::string name;   // unique; --case NAME
  std::string what;   // the hazard, in words
  std::string scene;  // scene spec ("builtin:atrium", a file)
  scene::View view;   // eye, target, up, fov, near, far (view.name = name)
  float radius = 0;   // world units; 0 = the scene's default
  // A copy of case `scale_of` with every length times some factor (scene "@scale=F", view and radius): its
  // error against its own reference must equal the original's within Options::scale_tolerance.
  std::string scale_of;
};

// The default suite, built on the built-in scenes (cases whose scene is not built into this binary are
// left out). Throws scene::SceneError only for a broken built-in.
std::vector<Case> default_cases();

// A case from explicit parameters (the form a reproducer prints for a randomised configuration).
// Throws std::runtime_error for a non-positive near, far <= near, a zero view direction.
Case custom_case(const std::string& scene, glm::vec3 eye, glm::vec3 target, float fov_y_deg, float near_plane,
                 float far_plane, float radius, glm::vec3 up = {0, 1, 0});

// The command-line arguments that select `c` on `aovar stress`: "--case NAME" for a default case, the
// explicit --scene/--eye/... form otherwise.
std::string case_arguments(const Case& c);

struct Options {
  compile::RunScope scope;                       // the manifest, rendering threads, jobs, the cache root
  std::vector<std::string> globs;                // --variants; empty = every variant
  bool shipped_only = false;                     // only the manifest's [ship] variants (with globs: both)
  std::vector<std::string> backends = {render::default_backend()};
  std::vector<Case> cases;                       // empty = default_cases()
  render::Extent size{96, 54};
  variants::CalibratedValues calibration;  // by algorithm (shipped parameter values)
  double pair_tolerance = 0.1;                   // |mediump - highp| or |r16f - r32f| per pixel
  double pair_share = 0.01;                      // share of pixels allowed beyond the tolerance
  double scale_tolerance = 0.005;                // |RMSE of a scaled case - RMSE of its original|
  std::filesystem::path out;                     // stress.json and stress.md (empty: no files)
  bool reuse = true;                             // keep results of an earlier stress.json whose inputs match
  int reference_rays = 64;                       // per pixel, for the reference error and the coverage probe
  // Renders (variant x case) per forked child process: the Vulkan driver never frees ~1.5 MB of compiled code per
  // render, so the whole space needs fresh processes. 0 = render in this process.
  long renders_per_process = 700;
  // The Vulkan backend runs mediump arithmetic in real fp16 (render::BackendOptions::mediump_as_fp16), as mobile GPUs
  // do; otherwise llvmpipe runs it in fp32 and mediump never differs from highp.
  bool mediump_fp16 = true;
  // --shard: this shard's cases only (stress/shard.h), OUT/shard.json written.
  shard::ShardSpec shard;
};

struct Check {  // one variant x case x backend
  std::string variant, case_name, backend;
  image::Health health;         // NaN, Inf and out-of-[0, 1] pixels of the image, of `pixels`
  std::string partner;          // the highp / r32f variant compared with (empty: none)
  double pair_max = 0, pair_share = 0;  // max |difference| and share of pixels beyond the tolerance
  double rmse = -1;             // against the ray-traced reference of the case (-1: not compared)
  std::string failure;          // empty = passed; else the reason in words
  std::string inputs_hash;      // programs, case, backend, size, parameters
};

struct VariantReport {
  std::string variant;
  bool shipped = false;
  int checks = 0;
  std::vector<std::size_t> failures;  // indices into Result::checks
};

struct Result {
  std::string shard_balance;  // sharded: this shard's share of the cases (shard::balance_line), else empty
  std::vector<Check> checks;
  std::vector<VariantReport> variants;  // sorted by key (pointers into checks)
  int shipped_failed = 0, failed = 0, reused = 0;
  double wall_s = 0;
};

using Progress = std::function<void(const std::string&)>;

// Throws std::runtime_error (manifest, scene, backend errors: one line each).
Result run_stress(const Options& options, const Progress& progress = {});

// The reproducer of a failed check.
std::string reproducer(const Options& options, const Check& check, const std::vector<Case>& cases);

nlohmann::json to_json(const Result& result, const Options& options);
std::string to_markdown(const Result& result, const Options& options);

}  // namespace aovar::stress
