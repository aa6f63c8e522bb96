#pragma once
// `aovar profile` and `aovar list --scene` (issue 8): what one scene, seen through its views, needs from the
// variant space, measured rather than assumed, and the variants it therefore does not need.
//  - depth per view (Embree primary rays, the linear depth the G-buffer stores): range, percentiles,
//    background share;
//  - r16f: the positions the AO pass reconstructs from r16f linear depth against r32f, per pixel (IEEE
//    half rounding of each pixel's depth times its view ray), as a share of the AO radius;
//  - the AO radius in pixels per pixel (the templates' ao_radius_px), so at which AO resolutions the pass
//    early-outs on most of the geometry (radius under one AO pixel), at which sample counts taps re-read
//    pixels, and which of SAO's MIP levels the taps reach;
//  - the camera paths: progressive halves against their full-sample form, flicker measured on the default backend;
//  - the renderer's declared G-buffer ([renderer] in the manifest): normal encodings, position buffer.
// Every dropped variant carries its reason with the evidence (numbers, views, manifest lines).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compile/run_scope.h"
#include "render/backend.h"
#include "render/frame.h"
#include "render/plan.h"
#include "scene/scene.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace aovar::profile {

struct Options {
  compile::RunScope scope;           // the manifest; threads (Embree, the renderer) and the compile cache of the flicker pair
  std::string scene = "builtin:atrium";
  std::vector<std::string> views;    // empty = every view of the scene
  render::Extent size{640, 360};     // the frame size the variants will run at
  float radius = 0;                  // world units; 0 = the scene's default
  // The two r16f tolerances are calibrated against rendered r16f/r32f pairs (bench/r16f, bench/README.md
  // "bench/r16f"): "visible" = `aovar stress`'s pair test, more than 1 % of the pixels off by more than 0.1.
  // Positions alone (buffered or no normals) never made a pair visible up to p99 = 22 % of R; the nearest
  // miss (0.95 % of pixels) was at 5.3 %, and under 5 % no pair passed 0.07 %. Depth-derived normals made
  // pairs visible from 2.9 deg (SAO, mostly); 5 deg misclassified 12 of 72 scene x radius x resolution
  // decisions, the former 10 deg 20 (19 of them visible pairs kept).
  double r16f_tolerance = 0.05;      // r16f is kept while its p99 position error stays under this share of R
  double normal_tolerance_deg = 5;   // r16f + depth-derived normals kept while their p95 angle error is under this
  double early_out_share = 0.5;      // a resolution is dropped when more geometry pixels than this early-out
  double flicker_tolerance = 0.005;  // progressive is kept while its flicker exceeds the full form's by less
  bool measure_flicker = true;       // render the progressive pair along moving camera paths (default backend)
};

struct ViewProfile {
  std::string view;
  float near_plane = 0, far_plane = 0;
  double background_share = 0;
  // Linear depth over the geometry pixels (0 when the view shows none).
  double depth_min = 0, depth_p05 = 0, depth_p50 = 0, depth_p95 = 0, depth_max = 0;
  // |P(r16f depth) - P(r32f depth)| in world units over the geometry pixels.
  double r16f_error_p99 = 0, r16f_error_max = 0;
  // Per manifest resolution: the angle (degrees, p95) between normals derived from r16f and from r32f depth
  // (forward differences one AO pixel apart, as the shaders' dFdx/dFdy), over pixels whose two neighbours
  // lie on the same surface.
  std::vector<std::pair<double, double>> r16f_normal_p95;
  // The angle (degrees, p50 / p90 over the geometry pixels) between the mesh's interpolated vertex normals,
  // what a normal buffer holds (turned to the camera's side of their face, as the G-buffer pass does), and
  // the faces the reference traces; -1 when not measured. Large where a
  // mesh's normals are smoothed across edges: variants reading buffered normals then tilt their hemisphere
  // away from the reference's, and normals derived from depth (the faces) match it better.
  double shading_normal_deg_p50 = -1, shading_normal_deg_p90 = -1;
  double shading_normal_share_over_10deg = -1;  // share of those pixels leaning more than 10 degrees
  // The AO radius in full-resolution pixels at the p95 / p50 / p05 depths (far, median, near).
  double radius_px_far = 0, radius_px_median = 0, radius_px_near = 0;
  int sao_levels_used = 0;           // MIP levels SAO's taps reach at the nearest 5 % of depths (1 = level 0)
  double camera_step = 0;            // world units the eye moves per frame along the view's path (0: static)
  double flicker_progressive = -1, flicker_full = -1;  // mean |AO_t - AO_t-1| (-1: not measured)
  std::vector<std::pair<double, double>> early_out;    // per manifest resolution: (resolution, share)
};

// One axis value (or a combination: axis "depth_format+normals", value "r16f+depth"; samples per
// resolution: value "32@0.25") and whether the scene needs it.
struct Decision {
  std::string axis, value;
  bool keep = true;
  std::string reason;  // why, with the evidence
};

struct Profile {
  std::string scene, scene_hash;
  float radius = 0;
  render::Extent size;
  std::vector<ViewProfile> views;
  std::vector<Decision> decisions;
  std::string flicker_pair;  // "progressive vs full" keys rendered for the flicker (empty: none)
};

using Progress = std::function<void(const std::string&)>;

// Throws std::runtime_error (scene, manifest, view, backend errors: one line each).
// With the scene, the manifest and its variant space (every variant after the rules, no --variants globs:
// the flicker pair is chosen from it) loaded by the caller, who prunes that same space afterwards;
// options.manifest is still read to compile the flicker pair, options.scene names the profile.
Profile profile_scene(const Options& options, const scene::Scene& scene, const variants::Manifest& manifest,
                      const variants::VariantSpace& space, const Progress& progress = {});
// Loads the scene (no views side file), the manifest and its space itself.
Profile profile_scene(const Options& options, const Progress& progress = {});

// The progressive variant and its full-sample form whose flicker stands for progressive rendering (the
// first progressive key of `space` whose progressive = false partner is in it too); empty strings when
// there is none.
std::pair<std::string, std::string> flicker_pair(const variants::Manifest& manifest,
                                                 const variants::VariantSpace& space);

struct Pruned {
  std::vector<std::string> kept;
  std::vector<std::pair<std::string, std::string>> dropped;  // key, reason ("<axis> <value>: <evidence>")
  std::vector<std::string> rules;  // parallel to dropped: the decision that drops it ("<axis> <value>")
};

// The variants of `space` the profile keeps, and every other one with the reason of its first failing
// decision; only the variants `globs` select (every one when empty).
Pruned prune(const variants::Manifest& manifest, const variants::VariantSpace& space, const Profile& profile,
             const std::vector<std::string>& globs = {});

// Runtime skipping of background pixels. Every AO template returns before its sampling loop where the
// G-buffer holds the background depth (ao_is_background: the early-out branch; no depth test or stencil is
// involved), so the AO pass should cost little more than a fetch per sky pixel where the sky is coherent.
// sky_sweep gives views from `base`'s eye pitched from 45 deg below its horizontal heading to 65 deg above,
// each with its background share (primary rays, at `size`); time_against_background times the AO pass (the
// draws of pass "ao") on each, interleaved round by round, median of `reps`.
struct SkyView {
  scene::View view;
  double background_share = 0;
};
std::vector<SkyView> sky_sweep(const scene::Scene& scene, const scene::View& base, int count, render::Extent size);

struct SkyTiming {
  double background_share = 0;
  double ao_ms = 0, total_ms = 0;  // medians
};
std::vector<SkyTiming> time_against_background(render::Backend& backend, const render::PipelinePlan& plan,
                                               const scene::Scene& scene, const std::vector<SkyView>& views,
                                               render::Extent size, int reps);

// A view where more than this share of the geometry pixels has buffered normals leaning over 10 degrees
// from their faces shows a mesh smoothed across its edges (Sponza's overview: over 10 %; the built-in scenes,
// the Stanford scans and the Van Gogh room: under 10 %; figures in docs/calibration.md).
inline constexpr double kSmoothedNormalsShare = 0.10;
// Whether some view of the profile shows such a lean: normals derived from depth then match the reference
// better than buffered ones (docs/calibration.md, "Buffered normals that lean from the faces").
bool buffered_normals_lean(const Profile& profile);

nlohmann::json to_json(const Profile& profile);
// The inverse of to_json (a profile.json read back); throws nlohmann::json errors on a malformed one.
Profile profile_from_json(const nlohmann::json& json);
std::string to_text(const Profile& profile);

}  // namespace aovar::profile
