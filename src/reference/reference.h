#pragma once
// Ray-traced ground truth for screen-space AO (docs/architecture.md, "Ground truth and error"): per pixel the primary ray through the pixel
// centre with the rasteriser's camera (render::make_frame_block), then cosine-weighted hemisphere rays
// from a low-discrepancy sequence, at most `radius` long, offset along the geometric normal. Embree 3 + TBB.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace aovar::reference {

enum class Mode {
  occlusion,   // binary visibility: a ray that hits anything within the radius is occluded
  obscurance,  // a hit at distance t occludes 1 - t / radius (linear falloff)
};
const char* mode_name(Mode m);                 // "occlusion", "obscurance"
Mode parse_mode(const std::string& text);     // throws std::invalid_argument naming the allowed values

// The most hemisphere rays per pixel a reference takes: 65,536 at 640x360 is 15 billion rays, hours of
// tracing; 2^31 made the sample table a bare std::bad_alloc (issue 54).
inline constexpr int kMaxRays = 65536;

struct ReferenceOptions {
  render::Extent size{640, 360};
  float radius = 0.0f;       // world units, > 0 (callers resolve fractions of the diagonal first)
  int rays = 256;            // hemisphere rays per pixel
  Mode mode = Mode::occlusion;
  int frame = 0;             // camera-path frame of the view (0 = its first pose)
  int threads = 0;           // TBB worker threads; 0 = all cores
  // Traced on the calling thread alone, beside other work: an arena of one and no process-wide cap, so that other
  // traces in the process keep their threads (threads is ignored). The image is the same either way.
  bool alone = false;
  std::filesystem::path cache_dir;  // empty = no cache
};

struct ReferenceImage {
  image::FloatImage visibility;  // in [0, 1], 1 = open; background pixels are 1
  image::FloatImage std_error;   // per-pixel standard error of `visibility`; background pixels are 0
  std::vector<std::uint8_t> background;  // 1 where the primary ray hits nothing (row 0 = bottom, as images)
  // Linear view depth of the primary hit (trace_depth's, from the same rays), +inf on background: where the
  // error lies in depth (metrics::error_breakdown). Cached with the image (reference/cache.h). Not in
  // write_reference's files.
  image::FloatImage depth;
  std::string key;               // cache key (scene hash, view, size, radius, rays, mode, frame, version)
  bool from_cache = false;
  double trace_s = 0;            // wall time spent tracing (0 when from the cache)
  std::uint64_t rays_traced = 0; // primary + hemisphere rays (0 when from the cache)
};

// Progress: fraction done in [0, 1] and seconds elapsed; called from the calling thread only.
using Progress = std::function<void(double fraction, double elapsed_s)>;

// Traces (or loads from the cache, reference/cache.h) the reference of one view. Throws std::runtime_error with
// a one-line message (bad options, Embree failure); a damaged cache entry is traced again with a warning, an
// unwritable cache makes it go on uncached: the cache never fails a run.
ReferenceImage trace_reference(const scene::Scene& scene, const scene::View& view, const ReferenceOptions& options,
                               const Progress& progress = {});

// What the camera sees, without AO: per pixel the linear view depth (distance along the view axis, the
// quantity the G-buffer stores) of the primary ray's hit, +inf where it hits nothing (row 0 = bottom).
// For scene profiles (src/profile): depth range, background share, r16f reconstruction.
struct DepthImage {
  image::FloatImage depth;
  std::vector<glm::vec3> normal;  // geometric normal facing the camera (0 on background)
  // The mesh's vertex normals interpolated at the hit and normalised, not turned to the camera (0 on
  // background, and where they cancel): how far they lean from `normal` is what a method reading buffered
  // normals sees that the reference, which traces the faces, does not.
  std::vector<glm::vec3> shading_normal;
};
DepthImage trace_depth(const scene::Scene& scene, const scene::View& view, render::Extent size, int frame = 0,
                       int threads = 0);

// The world radius of "R" given as world units ("1.0") or as a percentage of the scene's bounding-box
// diagonal ("1.5%"). Throws std::invalid_argument naming the text.
float resolve_radius(const std::string& text, const scene::Scene& scene);

// Files of a reference: <stem>.pfm (visibility), <stem>.stderr.pfm (standard error, -1 on background) and
// <stem>.png (preview), written atomically; read back by load_reference.
void write_reference(const std::filesystem::path& stem, const ReferenceImage& ref);
ReferenceImage load_reference(const std::filesystem::path& stem);

// The cache key of trace_reference (32 hex digits).
std::string cache_key(const scene::Scene& scene, const scene::View& view, const ReferenceOptions& options);

// RMSE of `a`'s visibility against `b`'s over the pixels that are surface in both (0 when none are): how far
// a reference is from a converged one of the same view (fewer rays against more, another ray API).
double surface_rmse(const ReferenceImage& a, const ReferenceImage& b);

// Summary over the non-background pixels (means are 1 and 0 when every pixel is background).
struct ReferenceStats {
  double mean_visibility = 1.0;
  double mean_std_error = 0.0;
  double background_share = 0.0;  // background pixels / all pixels
};
ReferenceStats reference_stats(const ReferenceImage& ref);

// `aovar reference`: loads the scene, traces (or loads) each view's reference and writes
// OUT/<view>.{pfm,stderr.pfm,png} and OUT/reference.json (atomically, the JSON last).
struct RunOptions {
  std::string scene = "builtin:atrium";
  std::filesystem::path views_file;
  std::vector<std::string> views;  // empty: the scene's first view
  std::string radius;              // as resolve_radius reads it; empty: the scene's ao_radius
  ReferenceOptions reference;      // radius is filled from `radius`
  std::filesystem::path out;
};
struct RunView {
  std::string view;
  ReferenceOptions options;
  ReferenceStats stats;
  std::string key;
  bool from_cache = false;
  double trace_s = 0;
  std::uint64_t rays_traced = 0;
  std::vector<std::string> files;  // relative to OUT
};
struct RunResult {
  std::string scene, scene_hash;
  std::size_t triangles = 0;
  std::vector<RunView> views;
  double wall_s = 0;
};
// `status(line, final)`: a progress line to show in place (final = false, throttled to about 10 a second)
// or a line to keep (final = true: one per view when it is done). Called from the calling thread only.
using RunStatus = std::function<void(const std::string& line, bool final)>;
RunResult run_reference(const RunOptions& options, const RunStatus& status = {});

}  // namespace aovar::reference
