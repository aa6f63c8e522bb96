#include "profile/profile.h"
#include "profile/half.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "compile/generate.h"
#include "util/stats.h"
#include "metrics/metrics.h"
#include "reference/reference.h"
#include "render/backend.h"
#include "render/plan.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"
#include "variants/key.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/schema.h"

namespace aovar::profile {
namespace {

using variants::Axis;
using json = nlohmann::json;

using util::percentile;  // nearest rank, as util::summarize

// What an r16f render target stores for a depth (profile/half.h: IEEE half, round to nearest even); depths
// beyond 65504 would become +inf, which the G-buffer never writes (it clamps to the background depth).
double as_half(float z) { return static_cast<double>(round_to_half(std::min(z, 65504.0f))); }

// The AO radius in pixels of a target `height` pixels tall at linear depth z (common/depth.glsl's
// ao_radius_px without its clamp to a quarter of the target).
double radius_px(const scene::View& v, float radius, double height, double z) {
  const double p11 = 1.0 / std::tan(glm::radians(static_cast<double>(v.fov_y_deg)) * 0.5);
  return radius * p11 * 0.5 * height / z;
}

std::string token(const variants::Manifest& m, Axis a, int i) { return m.value(a, i).text; }

// Mean |AO_t - AO_t-1| of `key` along the view's camera path.
double path_flicker(runner::VariantRunner& runner, const std::string& key, const scene::View& view, float radius) {
  const int v = runner::find_variant(runner.compiled(), key);
  if (v < 0) throw std::runtime_error("profile: " + key + " did not compile");
  auto prepared = runner.prepare(runner.plan(v, {}, true));
  // One frame of history first: a progressive variant averages its two halves from frame 1 on.
  return metrics::flicker(runner.render_path(*prepared, view, radius, 1, std::max(2, view.path_frames)));
}

// Per resolution: the p95 angle (degrees) between normals derived from r16f and from r32f depth, by forward
// differences one AO pixel apart; a neighbour more than 5 % deeper or nearer is another surface (an edge,
// where both are meaningless).
std::vector<std::pair<double, double>> r16f_normal_p95(const image::FloatImage& depth, const scene::View& view,
                                                      const std::vector<double>& resolutions) {
  const int w = depth.width, h = depth.height;
  const double tan_y = std::tan(glm::radians(static_cast<double>(view.fov_y_deg)) * 0.5);
  const double tan_x = tan_y * w / h;
  auto at = [&](int x, int y, bool half) {
    const double z = depth.pixels[static_cast<std::size_t>(y) * w + x];
    const double zz = half ? as_half(static_cast<float>(z)) : z;
    return glm::dvec3(((x + 0.5) / w * 2 - 1) * tan_x * zz, ((y + 0.5) / h * 2 - 1) * tan_y * zz, -zz);
  };
  std::vector<std::pair<double, double>> out;
  for (double res : resolutions) {
    const int d = std::max(1, static_cast<int>(std::lround(1.0 / res)));  // one AO pixel, in full-res pixels
    std::vector<double> angles;
    for (int y = 0; y + d < h; y += d)
      for (int x = 0; x + d < w; x += d) {
        const float z = depth.pixels[static_cast<std::size_t>(y) * w + x];
        const float zx = depth.pixels[static_cast<std::size_t>(y) * w + x + d];
        const float zy = depth.pixels[static_cast<std::size_t>(y + d) * w + x];
        if (!std::isfinite(z) || !std::isfinite(zx) || !std::isfinite(zy)) continue;
        if (std::abs(zx - z) > 0.05f * z || std::abs(zy - z) > 0.05f * z) continue;
        glm::dvec3 n32 = glm::cross(at(x + d, y, false) - at(x, y, false), at(x, y + d, false) - at(x, y, false));
        glm::dvec3 n16 = glm::cross(at(x + d, y, true) - at(x, y, true), at(x, y + d, true) - at(x, y, true));
        if (glm::length(n32) <= 0 || glm::length(n16) <= 0) {
          angles.push_back(90.0);  // r16f flattened the step to nothing: no normal at all
          continue;
        }
        angles.push_back(
            glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(n32), glm::normalize(n16)), -1.0, 1.0))));
      }
    out.emplace_back(res, percentile(angles, 0.95));
  }
  return out;
}

// What one view needs, from its traced depth: depth statistics, r16f errors, the radius in pixels and
// what it implies (SAO levels, early-outs per resolution), the camera's step.
ViewProfile profile_view(const scene::Scene& sc, const scene::View& view, const Options& o, float radius,
                         const std::vector<double>& resolutions) {
  const auto traced = reference::trace_depth(sc, view, o.size, 0, o.scope.threads);
  ViewProfile vp;
  vp.view = view.name;
  vp.near_plane = view.near_plane;
  vp.far_plane = view.far_plane;
  // The view ray of each pixel has view-space z = -1: P = z * ray, so |P16 - P32| = |z16 - z| |ray|.
  const double tan_y = std::tan(glm::radians(static_cast<double>(view.fov_y_deg)) * 0.5);
  const double tan_x = tan_y * o.size.width / o.size.height;
  std::vector<double> depths, errors, rpx, leans;
  const int w = o.size.width, h = o.size.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float z = traced.depth.pixels[static_cast<std::size_t>(y) * w + x];
      if (!std::isfinite(z)) continue;
      const double nx = ((x + 0.5) / w * 2 - 1) * tan_x, ny = ((y + 0.5) / h * 2 - 1) * tan_y;
      depths.push_back(z);
      errors.push_back(std::abs(as_half(z) - z) * std::sqrt(nx * nx + ny * ny + 1.0));
      rpx.push_back(radius_px(view, radius, h, z));
      const glm::vec3 shading = traced.shading_normal[static_cast<std::size_t>(y) * w + x];
      if (glm::dot(shading, shading) > 0.0f)
        // |dot|: the G-buffer pass turns a normal to the camera's side of its face, as the reference does.
        leans.push_back(glm::degrees(std::acos(std::min(
            std::abs(static_cast<double>(glm::dot(shading, traced.normal[static_cast<std::size_t>(y) * w + x]))), 1.0))));
    }
  vp.r16f_normal_p95 = r16f_normal_p95(traced.depth, view, resolutions);
  const double pixels = static_cast<double>(w) * h;
  vp.background_share = 1.0 - static_cast<double>(depths.size()) / pixels;
  if (!depths.empty()) {
    vp.depth_min = *std::min_element(depths.begin(), depths.end());
    vp.depth_max = *std::max_element(depths.begin(), depths.end());
    vp.depth_p05 = percentile(depths, 0.05), vp.depth_p50 = percentile(depths, 0.5), vp.depth_p95 = percentile(depths, 0.95);
    vp.r16f_error_p99 = percentile(errors, 0.99);
    vp.r16f_error_max = *std::max_element(errors.begin(), errors.end());
    if (!leans.empty()) {
      vp.shading_normal_deg_p50 = percentile(leans, 0.5), vp.shading_normal_deg_p90 = percentile(leans, 0.9);
      vp.shading_normal_share_over_10deg =
          static_cast<double>(std::count_if(leans.begin(), leans.end(), [](double a) { return a > 10.0; })) /
          static_cast<double>(leans.size());
    }
    vp.radius_px_far = radius_px(view, radius, h, vp.depth_p95);
    vp.radius_px_median = radius_px(view, radius, h, vp.depth_p50);
    vp.radius_px_near = radius_px(view, radius, h, vp.depth_p05);
    // SAO reads level floor(log2(tap distance)) - 3 (ao/sao.glsl, q' = 8), taps reach the radius (capped
    // at a quarter of the target like ao_radius_px).
    const double reach = std::min(vp.radius_px_near, 0.25 * std::min(w, h));
    vp.sao_levels_used = std::max(1, static_cast<int>(std::floor(std::log2(std::max(reach, 1.0)))) - 3 + 1);
    for (double res : resolutions) {
      const double share =
          static_cast<double>(std::count_if(rpx.begin(), rpx.end(), [&](double r) { return r * res < 1.0; })) /
          static_cast<double>(rpx.size());
      vp.early_out.emplace_back(res, share);
    }
  }
  vp.camera_step = view.path_frames > 1 ? glm::length(view.path_offset) / (view.path_frames - 1) : 0.0;
  return vp;
}

// Flicker of progressive halves along the moving paths (the static ones average their halves exactly),
// rendered on the default backend: the flicker pair of `space`, compiled for it alone.
void measure_flicker(Profile& p, const std::vector<const scene::View*>& views, const scene::Scene& sc,
                     const variants::Manifest& manifest, const variants::VariantSpace& space, const Options& o,
                     const Progress& say) {
  auto [progressive, full] = flicker_pair(manifest, space);
  if (progressive.empty()) return;
  p.flicker_pair = progressive + " vs " + full;
  say("measuring the flicker of " + p.flicker_pair);
  compile::CompileOptions co{o.scope};
  co.scope.targets = {variants::Target::vulkan};
  co.globs = {progressive, full};
  auto c = compile::compile_space(co);
  if (!c.ok()) throw std::runtime_error(c.diagnostics.empty() ? "profile: compile failed" : c.diagnostics.front());
  runner::RunnerOptions ro;
  ro.backend = render::default_backend();
  ro.device.threads = o.scope.threads;
  ro.size = o.size;
  runner::VariantRunner runner(c, ro);
  runner.use_scene(sc);
  for (std::size_t i = 0; i < views.size(); ++i) {
    if (p.views[i].camera_step <= 0) continue;
    p.views[i].flicker_progressive = path_flicker(runner, progressive, *views[i], p.radius);
    p.views[i].flicker_full = path_flicker(runner, full, *views[i], p.radius);
  }
}

void decide(Profile& p, Axis a, const std::string& value, bool keep, std::string reason) {
  p.decisions.push_back({std::string(variants::axis_info(a).name), value, keep, std::move(reason)});
}
void decide_pair(Profile& p, const std::string& axes, const std::string& values, bool keep, std::string reason) {
  p.decisions.push_back({axes, values, keep, std::move(reason)});
}

// r16f depth, by the positions it reconstructs (tolerances: Options, calibrated by bench/r16f against
// rendered r16f/r32f pairs, bench/README.md).
void decide_r16f_positions(Profile& p, const variants::Manifest& manifest, const Options& o) {
  for (const auto& v : manifest.axis_values(Axis::depth_format)) {
    if (v.text != "r16f") continue;
    const ViewProfile* worst = nullptr;
    for (const auto& vp : p.views)
      if (!worst || vp.r16f_error_p99 > worst->r16f_error_p99) worst = &vp;
    if (!worst) continue;
    const double share = worst->r16f_error_p99 / p.radius;
    // position = depth: a position buffer holds 32-bit positions whatever the depth format.
    decide_pair(p, "depth_format+position", v.text + "+depth", share <= o.r16f_tolerance,
                fmt::format("r16f linear depth moves reconstructed positions by {:.3g} (p99; max {:.3g}) on view {} "
                            "(depth {:.3g}-{:.3g}): {:.2f}% of the AO radius {:.3g}, tolerance {:.2f}%",
                            worst->r16f_error_p99, worst->r16f_error_max, worst->view, worst->depth_min,
                            worst->depth_max, 100 * share, p.radius, 100 * o.r16f_tolerance));
  }
}

// r16f depth with normals derived from it, per resolution.
void decide_r16f_normals(Profile& p, const variants::Manifest& manifest, const std::vector<double>& resolutions,
                         const Options& o) {
  for (std::size_t r = 0; r < resolutions.size(); ++r) {
    const ViewProfile* worst = nullptr;
    for (const auto& vp : p.views)
      if (r < vp.r16f_normal_p95.size() && (!worst || vp.r16f_normal_p95[r].second > worst->r16f_normal_p95[r].second))
        worst = &vp;
    if (!worst) continue;
    const double angle = worst->r16f_normal_p95[r].second;
    // normal_source (prune): the normals a variant's AO method uses, "depth" only when derived from depth.
    decide_pair(p, "depth_format+normal_source+resolution",
                "r16f+depth+" + manifest.value(Axis::resolution, static_cast<int>(r)).text,
                angle <= o.normal_tolerance_deg,
                fmt::format("normals derived from r16f depth at {}x resolution turn by {:.1f} deg (p95) from those of "
                            "r32f depth on view {} at {}x{}, tolerance {:.1f} deg",
                            resolutions[r], angle, worst->view, o.size.width, o.size.height, o.normal_tolerance_deg));
  }
}

// Resolutions at which the AO radius spans under one AO pixel on most of the geometry.
void decide_resolutions(Profile& p, const variants::Manifest& manifest, const std::vector<double>& resolutions,
                        const Options& o) {
  for (std::size_t r = 0; r < resolutions.size(); ++r) {
    const ViewProfile* worst = nullptr;
    for (const auto& vp : p.views)
      if (r < vp.early_out.size() && (!worst || vp.early_out[r].second > worst->early_out[r].second)) worst = &vp;
    if (!worst) continue;
    const double share = worst->early_out[r].second;
    decide(p, Axis::resolution, manifest.value(Axis::resolution, static_cast<int>(r)).text, share <= o.early_out_share,
           fmt::format("at {}x resolution the AO radius spans under one AO pixel (the pass's early-out: no AO) on "
                       "{:.0f}% of the geometry pixels of view {} (median radius {:.2f} px at full resolution), "
                       "threshold {:.0f}%",
                       resolutions[r], 100 * share, worst->view, worst->radius_px_median, 100 * o.early_out_share));
  }
}

// Samples, per resolution: taps spread over a disk of pi r^2 AO pixels; more taps than that re-read pixels.
void decide_samples(Profile& p, const variants::Manifest& manifest, const std::vector<double>& resolutions,
                    const Options& o) {
  const ViewProfile* widest = nullptr;  // the largest radius in pixels: the most room for taps
  for (const auto& vp : p.views)
    if (!widest || vp.radius_px_near > widest->radius_px_near) widest = &vp;
  for (std::size_t r = 0; widest && r < resolutions.size(); ++r)
    for (const auto& s : manifest.axis_values(Axis::samples)) {
      const double r_ao = std::min(widest->radius_px_near, 0.25 * std::min(o.size.width, o.size.height)) * resolutions[r];
      const double disk = std::numbers::pi * r_ao * r_ao;
      const double taps = std::stod(s.text);
      decide(p, Axis::samples, s.text + "@" + manifest.value(Axis::resolution, static_cast<int>(r)).text, taps <= disk,
             fmt::format("{} taps over a disk of {:.1f} AO pixels at {}x resolution (radius {:.2f} px at the nearest 5% "
                         "of depths, view {}){}",
                         s.text, disk, resolutions[r], r_ao, widest->view, taps <= disk ? "" : ": taps re-read pixels"));
    }
}

// Progressive halves, by their flicker against the full form's on the worst moving view.
void decide_progressive(Profile& p, const Options& o) {
  const ViewProfile* worst = nullptr;
  for (const auto& vp : p.views)
    if (vp.flicker_progressive >= 0 &&
        (!worst || vp.flicker_progressive - vp.flicker_full > worst->flicker_progressive - worst->flicker_full))
      worst = &vp;
  if (!worst) {
    decide(p, Axis::progressive, "true", true,
           o.measure_flicker ? "every view's camera is static: the two halves average to the full sample set"
                             : "flicker not measured (--no-flicker)");
    return;
  }
  const double extra = worst->flicker_progressive - worst->flicker_full;
  decide(p, Axis::progressive, "true", extra <= o.flicker_tolerance,
         fmt::format("progressive halves flicker {:.4f} against {:.4f} for all samples every frame ({}) along the "
                     "camera path of view {} ({:.3g} units a frame), tolerance +{:.4f}",
                     worst->flicker_progressive, worst->flicker_full, p.flicker_pair, worst->view, worst->camera_step,
                     o.flicker_tolerance));
}

// The G-buffer the renderer declares ([renderer] in the manifest): normal encodings, position buffer.
void decide_renderer_buffers(Profile& p, const variants::Manifest& manifest, const Options& o) {
  const auto display = util::display_path(o.scope.manifest.path());
  if (const auto& nb = manifest.renderer.normal_buffers)
    for (const auto& v : manifest.axis_values(Axis::normals)) {
      if (v.text == "depth") continue;
      bool has = std::find(nb->begin(), nb->end(), v.text) != nb->end();
      if (!has)
        decide(p, Axis::normals, v.text, false,
               fmt::format("the renderer writes no {} normal buffer ({}:{}: [renderer] normal_buffers)", v.text, display,
                           manifest.renderer.normal_buffers_pos.line));
    }
  if (manifest.renderer.position_buffer && !*manifest.renderer.position_buffer)
    decide(p, Axis::position, "position", false,
           fmt::format("the renderer writes no position buffer ({}:{}: [renderer] position_buffer = false)", display,
                       manifest.renderer.position_buffer_pos.line));
}

}  // namespace

std::pair<std::string, std::string> flicker_pair(const variants::Manifest& manifest,
                                                 const variants::VariantSpace& space) {
  std::set<std::string> keys;
  for (const auto& e : space.variants) keys.insert(e.key);
  for (const auto& key : keys) {
    const auto point = variants::parse_key(manifest, key);
    if (!point || variants::value_text(manifest, *point, Axis::progressive) != "true") continue;
    const auto full = variants::with_axis(manifest, key, Axis::progressive, "false");
    if (full && keys.count(*full)) return {key, *full};
  }
  return {};
}

Profile profile_scene(const Options& o, const Progress& progress) {
  const variants::Manifest& manifest = o.scope.manifest.get();
  const scene::Scene sc = scene::load_scene(o.scene);
  return profile_scene(o, sc, manifest, variants::build_space(manifest), progress);
}

Profile profile_scene(const Options& o, const scene::Scene& sc, const variants::Manifest& manifest,
                      const variants::VariantSpace& space, const Progress& progress) {
  const Progress say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  Profile p;
  p.scene = o.scene;
  p.scene_hash = sc.content_hash;
  p.radius = o.radius > 0 ? o.radius : sc.ao_radius;
  p.size = o.size;
  std::vector<const scene::View*> views;
  if (o.views.empty())
    for (const auto& v : sc.views) views.push_back(&v);
  else
    for (const auto& name : o.views) views.push_back(&sc.view(name));
  std::vector<double> resolutions;
  for (const auto& v : manifest.axis_values(Axis::resolution)) resolutions.push_back(std::stod(v.text));

  for (const scene::View* view : views) {
    say("tracing the depth of " + view->name);
    p.views.push_back(profile_view(sc, *view, o, p.radius, resolutions));
  }
  const bool moving = std::any_of(p.views.begin(), p.views.end(), [](const ViewProfile& v) { return v.camera_step > 0; });
  if (o.measure_flicker && moving) measure_flicker(p, views, sc, manifest, space, o, say);

  // Decisions, axis value by axis value.
  decide_r16f_positions(p, manifest, o);
  decide_r16f_normals(p, manifest, resolutions, o);
  decide_resolutions(p, manifest, resolutions, o);
  decide_samples(p, manifest, resolutions, o);
  decide_progressive(p, o);
  decide_renderer_buffers(p, manifest, o);
  return p;
}

// The normals a variant's AO method uses: "depth" (derived from depth: the normals axis says depth and the
// positions come from depth, or the method derives them itself, [algorithms] normals_from_depth),
// "position" (derived from the 32-bit position buffer), "buffer" (a normal buffer), "none" (the method uses
// no normals: Crytek, VO, unsharp masking).
static std::string normal_source(const variants::Manifest& m, const variants::VariantEntry& e) {
  auto value = [&](Axis a) {
    int i = e.point[variants::index(a)];
    return i < 0 ? std::string() : m.value(a, i).text;
  };
  const variants::Algorithm* algorithm = nullptr;
  for (const auto& a : m.algorithms)
    if (a.name == value(Axis::algorithm)) algorithm = &a;
  if (!algorithm) return "none";
  const bool reads_normals =
      std::find(algorithm->reads.begin(), algorithm->reads.end(), Axis::normals) != algorithm->reads.end();
  if (!reads_normals) return algorithm->normals_from_depth ? "depth" : "none";
  if (value(Axis::normals) != "depth") return "buffer";
  return value(Axis::position) == "position" ? "position" : "depth";
}

Pruned prune(const variants::Manifest& m, const variants::VariantSpace& space, const Profile& p,
             const std::vector<std::string>& globs) {
  auto split = [](const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t end; (end = text.find('+', start)) != std::string::npos; start = end + 1)
      parts.push_back(text.substr(start, end - start));
    parts.push_back(text.substr(start));
    return parts;
  };
  auto value_of = [&](const variants::VariantEntry& e, const std::string& axis) -> std::string {
    if (axis == "normal_source") return normal_source(m, e);
    auto a = variants::find_axis(axis);
    int i = a ? e.point[variants::index(*a)] : -1;
    return i < 0 ? std::string() : token(m, *a, i);  // collapsed: the variant does not read the axis
  };
  // A decision applies when the variant has every named value (samples: "count@resolution").
  auto applies = [&](const variants::VariantEntry& e, const Decision& d) {
    auto axes = split(d.axis), values = split(d.value);
    for (std::size_t i = 0; i < axes.size() && i < values.size(); ++i) {
      std::string v = value_of(e, axes[i]);
      if (axes[i] == "samples") v += "@" + value_of(e, "resolution");
      if (v != values[i]) return false;
    }
    return true;
  };
  Pruned out;
  for (const auto& e : space.variants) {
    if (!util::glob_any(globs, e.key)) continue;
    auto why = std::find_if(p.decisions.begin(), p.decisions.end(), [&](const Decision& d) { return !d.keep && applies(e, d); });
    if (why != p.decisions.end()) {
      out.dropped.emplace_back(e.key, why->axis + " " + why->value + ": " + why->reason);
      out.rules.push_back(why->axis + " " + why->value);
    } else {
      out.kept.push_back(e.key);
    }
  }
  return out;
}

std::vector<SkyView> sky_sweep(const scene::Scene& sc, const scene::View& base, int count, render::Extent size) {
  const glm::vec3 d = base.target - base.eye;
  glm::vec3 heading = glm::vec3(d.x, 0.0f, d.z);
  heading = glm::length(heading) > 0 ? glm::normalize(heading) : glm::vec3(0, 0, -1);
  const float distance = std::max(glm::length(d), 1e-3f);
  std::vector<SkyView> out;
  for (int i = 0; i < count; ++i) {
    const float pitch = glm::radians(-45.0f + 110.0f * static_cast<float>(i) / static_cast<float>(std::max(1, count - 1)));
    SkyView v;
    v.view = base;
    v.view.name = fmt::format("pitch{:+.0f}", glm::degrees(pitch));
    v.view.target = base.eye + distance * (std::cos(pitch) * heading + std::sin(pitch) * glm::vec3(0, 1, 0));
    v.view.up = {0, 1, 0};
    v.view.path_offset = glm::vec3(0.0f);
    const auto traced = reference::trace_depth(sc, v.view, size);
    v.background_share = static_cast<double>(std::count_if(traced.depth.pixels.begin(), traced.depth.pixels.end(),
                                                           [](float z) { return !std::isfinite(z); })) /
                         static_cast<double>(traced.depth.pixels.size());
    out.push_back(v);
  }
  std::sort(out.begin(), out.end(), [](const SkyView& a, const SkyView& b) { return a.background_share < b.background_share; });
  return out;
}

std::vector<SkyTiming> time_against_background(render::Backend& backend, const render::PipelinePlan& plan,
                                               const scene::Scene& sc, const std::vector<SkyView>& views,
                                               render::Extent size, int reps) {
  backend.set_scene(sc);
  auto prepared = backend.prepare(plan, size);
  const auto ran = render::plan_for_size(plan, size);  // the draws the backend times
  std::vector<std::vector<double>> ao(views.size()), total(views.size());
  for (std::size_t i = 0; i < views.size(); ++i)  // warm-up: first frames compile and fault in
    backend.render(*prepared, {&views[i].view, 0, true, sc.ao_radius});
  for (int r = 0; r < reps; ++r)
    for (std::size_t k = 0; k < views.size(); ++k) {
      const std::size_t i = (k + static_cast<std::size_t>(r)) % views.size();  // rotate the order each round
      const auto ms = backend.render(*prepared, {&views[i].view, 0, true, sc.ao_radius});
      double a = 0, t = 0;
      for (std::size_t d = 0; d < ms.size() && d < ran.draws.size(); ++d) {
        t += ms[d];
        if (ran.draws[d].pass == "ao") a += ms[d];
      }
      ao[i].push_back(a);
      total[i].push_back(t);
    }
  std::vector<SkyTiming> out;
  for (std::size_t i = 0; i < views.size(); ++i)
    out.push_back({views[i].background_share, percentile(ao[i], 0.5), percentile(total[i], 0.5)});
  return out;
}

json to_json(const Profile& p) {
  json views = json::array();
  for (const auto& v : p.views) {
    json early = json::array();
    for (const auto& [res, share] : v.early_out) early.push_back({{"resolution", res}, {"share", share}});
    json normals = json::array();
    for (const auto& [res, deg] : v.r16f_normal_p95) normals.push_back({{"resolution", res}, {"degrees", deg}});
    views.push_back({{"view", v.view}, {"near", v.near_plane}, {"far", v.far_plane}, {"background_share", v.background_share},
                     {"depth", {{"min", v.depth_min}, {"p05", v.depth_p05}, {"p50", v.depth_p50}, {"p95", v.depth_p95},
                                {"max", v.depth_max}}},
                     {"r16f_position_error", {{"p99", v.r16f_error_p99}, {"max", v.r16f_error_max}}},
                     {"r16f_normal_error_deg_p95", normals},
                     {"shading_normal_deg", {{"p50", v.shading_normal_deg_p50}, {"p90", v.shading_normal_deg_p90},
                                             {"share_over_10", v.shading_normal_share_over_10deg}}},
                     {"radius_px", {{"far", v.radius_px_far}, {"median", v.radius_px_median}, {"near", v.radius_px_near}}},
                     {"sao_levels_used", v.sao_levels_used}, {"camera_step", v.camera_step},
                     {"flicker", {{"progressive", v.flicker_progressive}, {"full", v.flicker_full}}},
                     {"early_out", early}});
  }
  json decisions = json::array();
  for (const auto& d : p.decisions)
    decisions.push_back({{"axis", d.axis}, {"value", d.value}, {"keep", d.keep}, {"reason", d.reason}});
  return {{"schema_version", util::kSchemaVersion}, {"tool", "aovar profile"}, {"scene", p.scene}, {"scene_hash", p.scene_hash}, {"radius", p.radius},
          {"size", fmt::format("{}x{}", p.size.width, p.size.height)}, {"flicker_pair", p.flicker_pair},
          {"views", views}, {"decisions", decisions}};
}

bool buffered_normals_lean(const Profile& p) {
  return std::any_of(p.views.begin(), p.views.end(),
                     [](const ViewProfile& v) { return v.shading_normal_share_over_10deg > kSmoothedNormalsShare; });
}

Profile profile_from_json(const json& j) {
  auto extent = [](const std::string& text) {
    render::Extent e;
    if (std::sscanf(text.c_str(), "%dx%d", &e.width, &e.height) != 2) throw std::runtime_error("bad size '" + text + "'");
    return e;
  };
  auto pairs = [](const json& list, const char* value) {
    std::vector<std::pair<double, double>> out;
    for (const auto& e : list) out.emplace_back(e.at("resolution").get<double>(), e.at(value).get<double>());
    return out;
  };
  Profile p;
  p.scene = j.at("scene");
  p.scene_hash = j.at("scene_hash");
  p.radius = j.at("radius");
  p.size = extent(j.at("size"));
  p.flicker_pair = j.at("flicker_pair");
  for (const auto& v : j.at("views")) {
    ViewProfile vp;
    vp.view = v.at("view");
    vp.near_plane = v.at("near");
    vp.far_plane = v.at("far").is_null() ? std::numeric_limits<float>::infinity() : v.at("far").get<float>();
    vp.background_share = v.at("background_share");
    const json& d = v.at("depth");
    vp.depth_min = d.at("min"), vp.depth_p05 = d.at("p05"), vp.depth_p50 = d.at("p50"), vp.depth_p95 = d.at("p95");
    vp.depth_max = d.at("max");
    vp.r16f_error_p99 = v.at("r16f_position_error").at("p99");
    vp.r16f_error_max = v.at("r16f_position_error").at("max");
    vp.r16f_normal_p95 = pairs(v.at("r16f_normal_error_deg_p95"), "degrees");
    if (v.contains("shading_normal_deg")) {  // absent from profiles written before it was measured
      vp.shading_normal_deg_p50 = v.at("shading_normal_deg").at("p50");
      vp.shading_normal_deg_p90 = v.at("shading_normal_deg").at("p90");
      vp.shading_normal_share_over_10deg = v.at("shading_normal_deg").at("share_over_10");
    }
    const json& r = v.at("radius_px");
    vp.radius_px_far = r.at("far"), vp.radius_px_median = r.at("median"), vp.radius_px_near = r.at("near");
    vp.sao_levels_used = v.at("sao_levels_used");
    vp.camera_step = v.at("camera_step");
    vp.flicker_progressive = v.at("flicker").at("progressive");
    vp.flicker_full = v.at("flicker").at("full");
    vp.early_out = pairs(v.at("early_out"), "share");
    p.views.push_back(std::move(vp));
  }
  for (const auto& d : j.at("decisions")) p.decisions.push_back({d.at("axis"), d.at("value"), d.at("keep"), d.at("reason")});
  return p;
}

std::string to_text(const Profile& p) {
  std::string s = fmt::format("scene {} at {}x{}, AO radius {:.3g}\n", p.scene, p.size.width, p.size.height, p.radius);
  for (const auto& v : p.views) {
    s += fmt::format("view {}: near {:.3g} far {:.3g}; background {:.1f}% of pixels; depth {:.3g} / {:.3g} / {:.3g} / {:.3g} / "
                     "{:.3g} (min / p05 / median / p95 / max)\n",
                     v.view, v.near_plane, v.far_plane, 100 * v.background_share, v.depth_min, v.depth_p05, v.depth_p50,
                     v.depth_p95, v.depth_max);
    std::string normals;
    for (const auto& [res, deg] : v.r16f_normal_p95) normals += fmt::format("{}{}x {:.1f}", normals.empty() ? "" : ", ", res, deg);
    s += fmt::format("  r16f: position error {:.3g} (p99), {:.3g} (max); depth-normal error (p95, deg) {}\n", v.r16f_error_p99,
                     v.r16f_error_max, normals);
    if (v.shading_normal_deg_p50 >= 0)
      s += fmt::format("  buffered normals lean from the faces the reference traces by {:.1f} / {:.1f} deg (p50 / p90), "
                       "over 10 deg on {:.0f}% of the geometry{}\n",
                       v.shading_normal_deg_p50, v.shading_normal_deg_p90, 100 * v.shading_normal_share_over_10deg,
                       v.shading_normal_share_over_10deg > kSmoothedNormalsShare
                           ? ": buffered normals off their faces (smoothed across edges), so normals = depth matches the reference better"
                           : "");
    s += fmt::format("  AO radius {:.1f} / {:.1f} / {:.1f} px (far / median / "
                     "near); SAO MIP levels used {}\n",
                     v.radius_px_far, v.radius_px_median, v.radius_px_near,
                     v.sao_levels_used);
    std::string early;
    for (const auto& [res, share] : v.early_out) early += fmt::format("{}{}x {:.0f}%", early.empty() ? "" : ", ", res, 100 * share);
    s += "  early-out (radius under one AO pixel): " + early + "\n";
    if (v.camera_step > 0)
      s += v.flicker_progressive >= 0
               ? fmt::format("  camera moves {:.3g} a frame; flicker progressive {:.4f}, full {:.4f}\n", v.camera_step,
                             v.flicker_progressive, v.flicker_full)
               : fmt::format("  camera moves {:.3g} a frame\n", v.camera_step);
  }
  for (const auto& d : p.decisions)
    if (!d.keep || d.axis != "samples") s += fmt::format("{} {} {}: {}\n", d.keep ? "keep" : "drop", d.axis, d.value, d.reason);
  int dropped_samples = 0;
  for (const auto& d : p.decisions) dropped_samples += d.axis == "samples" && !d.keep;
  if (dropped_samples == 0) s += "keep every sample count: no count has more taps than its disk has pixels\n";
  return s;
}

}  // namespace aovar::profile
