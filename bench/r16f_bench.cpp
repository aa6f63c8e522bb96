// bench/r16f: does r16f linear depth visibly change the AO where `aovar profile` says it does?
//
// The profile drops (a) r16f depth when the p99 of its position reconstruction error exceeds a share of the
// AO radius R (--r16f-tolerance) and (b) r16f depth with depth-derived normals at an AO resolution when the
// p95 angle between r16f- and r32f-derived normals exceeds an angle. This program measures both statistics
// with profile::profile_scene and, for the same scene, view, radius and frame size, renders on lavapipe
// every pair of variants that differ only in the depth format (same method, samples, normals, blur,
// resolution, precision), with the calibrated parameters, and compares the two images:
//   share  = pixels where |AO(r16f) - AO(r32f)| > 0.1, over all pixels: `aovar stress`'s precision-pair
//            test (--pair-tolerance 0.1), which calls a pair different when share > 1 % (--pair-share);
//   mean   = mean |AO(r16f) - AO(r32f)| over the geometry pixels;
//   d_rmse = RMSE(r16f) / RMSE(r32f) - 1, both against the Embree reference of the view.
// Pairs fall in two groups: "position" (buffered RGB8 normals, or methods that read no normals: Crytek,
// unsharp masking, VO), which r16f reaches only through positions (statistic a), and "normals" (normals
// derived from depth: Alchemy, GTAO, HBAO, StarCraft II with ndep, and SAO), which it reaches through
// both (statistic b at the pair's resolution). The AO radius is swept (factors of the scene's radius) to
// spread p99 / R. Writes OUT/r16f.json (every pair) and OUT/r16f.md (the tables), printed too.
//
// Usage: aovar_r16f_bench [--manifest M] [--size WxH] [--factors 0.5,1,2] [--rays N] [--out DIR] [SCENE...]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calibrate/file.h"
#include "compile/cache.h"
#include "compile/generate.h"
#include "metrics/metrics.h"
#include "profile/profile.h"
#include "reference/reference.h"
#include "render/backend.h"
#include "render/plan.h"
#include "scene/scene.h"
#include "variants/manifest.h"
#include "util/fs.h"

using namespace aovar;
using json = nlohmann::json;

namespace {

constexpr double kPairTolerance = 0.1;  // stress::Options::pair_tolerance
constexpr double kPairShare = 0.01;     // stress::Options::pair_share

struct Pair {
  std::string key16, key32, algorithm;
  bool normals_from_depth = false;  // the AO pass derives normals from (r16f) depth
  double resolution = 1;
  int v16 = -1, v32 = -1;
};

struct Row {  // one pair on one scene / radius / view
  std::string scene, view, algorithm, key16;
  double factor = 1, radius = 0, resolution = 1;
  bool normals_from_depth = false;
  double pos_p99_over_r = 0, angle_p95 = 0;  // the profile's statistics for this view (angle: at resolution)
  double share = 0, mean = 0, max = 0, rmse16 = 0, rmse32 = 0;
  bool visible() const { return share > kPairShare; }
  double d_rmse() const { return rmse32 > 0 ? rmse16 / rmse32 - 1 : 0; }
};

std::string token(const std::string& key, int i) {
  std::size_t start = 0;
  for (int k = 0; k < i; ++k) start = key.find('-', start) + 1;
  return key.substr(start, key.find('-', start) - start);
}

// Thresholds: the share of points a threshold T classifies right (drop where x > T, visible or not).
struct Split {
  int n = 0, visible = 0, dropped_visible = 0, dropped_invisible = 0, kept_visible = 0;
  double lowest_visible = -1, highest_invisible = -1;  // x at the edges of the two classes
};
Split split(const std::vector<std::pair<double, bool>>& points, double threshold) {
  Split s;
  for (auto [x, vis] : points) {
    ++s.n;
    s.visible += vis;
    if (x > threshold) (vis ? s.dropped_visible : s.dropped_invisible)++;
    else s.kept_visible += vis;
    if (vis && (s.lowest_visible < 0 || x < s.lowest_visible)) s.lowest_visible = x;
    if (!vis && x > s.highest_invisible) s.highest_invisible = x;
  }
  return s;
}

std::string describe(const char* what, const std::vector<std::pair<double, bool>>& points, double current, double scale,
                     const char* unit) {
  auto s = split(points, current);
  auto x = [&](double v) { return v < 0 ? std::string("none") : fmt::format("{:.3g}{}", v * scale, unit); };
  std::string out = fmt::format(
      "- {}: {} points, {} visible. At the current threshold {:.3g}{}: {} visible dropped, {} invisible dropped, {} "
      "visible kept. Lowest x with a visible pair: {}; highest x without one: {}.\n",
      what, s.n, s.visible, current * scale, unit, s.dropped_visible, s.dropped_invisible, s.kept_visible,
      x(s.lowest_visible), x(s.highest_invisible));
  // The threshold with the fewest misclassified points (ties: the largest, which keeps the most), among
  // the midpoints between consecutive distinct x.
  std::vector<double> xs;
  for (auto [x, v] : points) xs.push_back(x);
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  int best_err = 1 << 30;
  double best = current;
  for (std::size_t i = 0; i + 1 <= xs.size(); ++i) {
    const double t = i + 1 < xs.size() ? 0.5 * (xs[i] + xs[i + 1]) : xs[i];
    auto c = split(points, t);
    const int err = c.dropped_invisible + c.kept_visible;
    if (err <= best_err) best_err = err, best = t;
  }
  auto b = split(points, best);
  out += fmt::format("  Fewest misclassified: threshold {:.3g}{} ({} visible kept, {} invisible dropped).\n", best * scale, unit,
                     b.kept_visible, b.dropped_invisible);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string manifest = "shader_src/aovar.toml";
  render::Extent size{640, 360};
  std::vector<double> factors = {0.5, 1, 2};
  int rays = 64;
  std::filesystem::path out = "bench-r16f";
  std::vector<std::string> scenes, globs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench/r16f: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--manifest") manifest = next();
    else if (a == "--size") {
      if (std::sscanf(next().c_str(), "%dx%d", &size.width, &size.height) != 2) return std::fprintf(stderr, "bad --size\n"), 2;
    } else if (a == "--factors") {
      factors.clear();
      std::string s = next();
      for (std::size_t p = 0; p < s.size();) {
        std::size_t e = s.find(',', p);
        factors.push_back(std::stod(s.substr(p, e - p)));
        p = e == std::string::npos ? s.size() : e + 1;
      }
    } else if (a == "--rays") rays = std::stoi(next());
    else if (a == "--out") out = next();
    else if (a == "--variants") globs.push_back(next());  // instead of the pairs below (bench/r16f's smoke mode)
    else scenes.push_back(a);
  }
  if (scenes.empty()) scenes = {"builtin:atrium", "builtin:far", "builtin:cornell", "builtin:spheres", "builtin:stairs"};

  // Every r16f/r32f pair: the ten methods at 8 samples, p0, bsep, highp, default reconstruction, at the
  // three resolutions; buffered RGB8 normals and normals from depth where the method reads normals.
  compile::CompileOptions co;
  co.scope.targets = {variants::Target::vulkan};
  co.globs = {"*-s08-p0-nrgb8-zdep-rst-d*-bsep-x*-hp", "*-s08-p0-ndep-zdep-rst-d*-bsep-x*-hp",
              "*-s08-p0-ndep-zdep-_r-d*-bsep-x*-hp"};
  if (!globs.empty()) co.globs = globs;
  co.scope.cache_dir = compile::CompileCache::default_dir();
  co.scope.manifest = manifest;
  auto c = compile::compile_space(co);
  if (!c.ok()) {
    std::fprintf(stderr, "bench/r16f: %s\n", c.diagnostics.empty() ? "compile failed" : c.diagnostics.front().c_str());
    return 1;
  }
  std::map<std::string, int> index;
  for (std::size_t i = 0; i < c.space.variants.size(); ++i) index[c.space.variants[i].key] = static_cast<int>(i);
  const std::set<std::string> derive = {"alchemy", "gtao", "hbao", "sc2", "sao"};  // read normals; ndep = derived
  std::vector<Pair> pairs;
  for (const auto& [key, v] : index) {
    if (token(key, 6) != "d16") continue;
    Pair p;
    p.key16 = key;
    p.key32 = key;
    p.key32.replace(p.key32.find("-d16-"), 5, "-d32-");
    if (!index.count(p.key32)) continue;
    p.v16 = v, p.v32 = index[p.key32];
    p.algorithm = token(key, 0);
    p.normals_from_depth = token(key, 3) == "ndep" && derive.count(p.algorithm);
    p.resolution = 1.0 / std::stod(token(key, 8).substr(1));
    pairs.push_back(p);
  }
  std::fprintf(stderr, "bench/r16f: %zu pairs, %zu scenes, radius factors %zu, %dx%d\n", pairs.size(), scenes.size(),
               factors.size(), size.width, size.height);

  std::map<std::string, render::ParamOverrides> calibration;
  const auto cal_path = std::filesystem::path(manifest).parent_path() / "calibration.json";
  if (std::filesystem::exists(cal_path)) calibration = calibrate::load_calibration(cal_path, variants::load_manifest(manifest));

  render::BackendOptions bo;
  bo.threads = 2;
  auto backend = render::make_backend("lavapipe", bo);
  std::vector<std::unique_ptr<render::PreparedPipeline>> prepared(c.space.variants.size());

  std::vector<Row> rows;
  for (const auto& spec : scenes) {
    const auto sc = scene::load_scene(spec);
    backend->set_scene(sc);
    for (double factor : factors) {
      profile::Options po;
      po.scope.manifest = manifest;
      po.scene = spec;
      po.size = size;
      po.radius = static_cast<float>(sc.ao_radius * factor);
      po.measure_flicker = false;
      const auto prof = profile::profile_scene(po);
      for (const auto& view : sc.views) {
        std::fprintf(stderr, "bench/r16f: %s R x%g %s\n", spec.c_str(), factor, view.name.c_str());
        const auto vp = std::find_if(prof.views.begin(), prof.views.end(), [&](const auto& v) { return v.view == view.name; });
        reference::ReferenceOptions ro;
        ro.size = size;
        ro.radius = prof.radius;
        ro.rays = rays;
        ro.threads = 2;
        ro.cache_dir = compile::CompileCache::default_dir();  // what aovar reference and measure use
        const auto ref = reference::trace_reference(sc, view, ro);
        std::map<int, image::FloatImage> images;
        auto image_of = [&](int v) -> const image::FloatImage& {
          auto it = images.find(v);
          if (it != images.end()) return it->second;
          if (!prepared[v]) {
            auto cal = calibration.find(token(c.space.variants[v].key, 0));
            prepared[v] = backend->prepare(
                render::plan_pipeline(c, v, variants::Target::vulkan, cal == calibration.end() ? render::ParamOverrides{} : cal->second),
                size);
          }
          backend->render(*prepared[v], {&view, 0, true, prof.radius});
          return images[v] = backend->read_result(*prepared[v]);
        };
        for (const auto& p : pairs) {
          const auto& a = image_of(p.v16);
          const auto& b = image_of(p.v32);
          Row r;
          r.scene = spec, r.view = view.name, r.algorithm = p.algorithm, r.key16 = p.key16;
          r.factor = factor, r.radius = prof.radius, r.resolution = p.resolution;
          r.normals_from_depth = p.normals_from_depth;
          r.pos_p99_over_r = vp->r16f_error_p99 / prof.radius;
          for (const auto& [res, deg] : vp->r16f_normal_p95)
            if (std::abs(res - p.resolution) < 1e-6) r.angle_p95 = deg;
          long beyond = 0, geometry = 0;
          double sum = 0;
          for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            if (!std::isfinite(a.pixels[i]) || !std::isfinite(b.pixels[i])) continue;
            const double d = std::abs(double(a.pixels[i]) - double(b.pixels[i]));
            beyond += d > kPairTolerance;
            r.max = std::max(r.max, d);
            if (!ref.background[i]) sum += d, ++geometry;
          }
          r.share = static_cast<double>(beyond) / static_cast<double>(a.pixels.size());
          r.mean = geometry ? sum / static_cast<double>(geometry) : 0;
          r.rmse16 = metrics::compare(a, ref.visibility, ref.background).rmse;
          r.rmse32 = metrics::compare(b, ref.visibility, ref.background).rmse;
          rows.push_back(r);
        }
      }
    }
  }

  // Tables.
  auto name = [](const std::string& spec) {
    auto slash = spec.find_last_of('/');
    return slash == std::string::npos ? spec : spec.substr(slash + 1);
  };
  std::string md = fmt::format(
      "lavapipe {}x{}, {} pairs per view (8 samples, separable blur, highp, calibrated), reference {} rays; share = "
      "pixels with |AO(r16f) - AO(r32f)| > {} (visible: share > {:.0f} %, `aovar stress`'s pair test)\n\n",
      size.width, size.height, pairs.size(), rays, kPairTolerance, 100 * kPairShare);
  // (a) per view: p99 / R against the worst position-only pair (any resolution).
  md += "### (a) position error: pairs with buffered normals or no normals\n\n"
        "| scene | R | view | p99 pos err / R | worst pair | share > 0.1 | mean abs diff | RMSE change | visible pairs |\n"
        "|---|---:|---|---:|---|---:|---:|---:|---:|\n";
  std::vector<std::pair<double, bool>> pos_points, pos_decisions, normal_points, normal_decisions, normal_points_but_sao;
  std::map<std::string, std::pair<double, bool>> pos_by_config;  // scene|factor: max p99/R, any visible
  std::map<std::string, std::pair<double, bool>> normal_by_config;
  for (std::size_t i = 0; i < rows.size();) {
    std::size_t j = i;
    while (j < rows.size() && rows[j].scene == rows[i].scene && rows[j].factor == rows[i].factor && rows[j].view == rows[i].view) ++j;
    const Row* worst = nullptr;
    int visible = 0, n = 0;
    double worst_rmse = 0;
    for (std::size_t k = i; k < j; ++k) {
      if (rows[k].normals_from_depth) continue;
      ++n;
      visible += rows[k].visible();
      if (!worst || rows[k].share > worst->share) worst = &rows[k];
      if (std::abs(rows[k].d_rmse()) > std::abs(worst_rmse)) worst_rmse = rows[k].d_rmse();
    }
    if (worst) {
      md += fmt::format("| {} | {:.3g} | {} | {:.2f} % | {} x{} | {:.2f} % | {:.4f} | {:+.1f} % | {}/{} |\n", name(worst->scene),
                        worst->radius, worst->view, 100 * worst->pos_p99_over_r, worst->algorithm,
                        1 / worst->resolution, 100 * worst->share, worst->mean, 100 * worst_rmse, visible, n);
      pos_points.emplace_back(worst->pos_p99_over_r, worst->visible());
      auto& cfg = pos_by_config[fmt::format("{}|{}", worst->scene, worst->factor)];
      cfg.first = std::max(cfg.first, worst->pos_p99_over_r);
      cfg.second = cfg.second || worst->visible();
    }
    i = j;
  }
  // (b) per view and resolution: p95 angle against the worst depth-normal pair, with the position-only
  // worst at the same resolution beside it (where that is visible too, (a) decides).
  md += "\n### (b) normals derived from depth, per AO resolution\n\n"
        "| scene | R | view | res | p95 angle | p99 pos err / R | worst pair | share > 0.1 | mean abs diff | RMSE change | "
        "worst but SAO: share | position-only worst share |\n|---|---:|---|---:|---:|---:|---|---:|---:|---:|---|---:|\n";
  for (std::size_t i = 0; i < rows.size();) {
    std::size_t j = i;
    while (j < rows.size() && rows[j].scene == rows[i].scene && rows[j].factor == rows[i].factor && rows[j].view == rows[i].view) ++j;
    for (double res : {1.0, 0.5, 0.25}) {
      const Row *worst = nullptr, *pos = nullptr, *other = nullptr;  // other: the worst method but SAO
      double worst_rmse = 0;
      for (std::size_t k = i; k < j; ++k) {
        if (std::abs(rows[k].resolution - res) > 1e-6) continue;
        if (!rows[k].normals_from_depth) {
          if (!pos || rows[k].share > pos->share) pos = &rows[k];
          continue;
        }
        if (!worst || rows[k].share > worst->share) worst = &rows[k];
        if (rows[k].algorithm != "sao" && (!other || rows[k].share > other->share)) other = &rows[k];
        if (std::abs(rows[k].d_rmse()) > std::abs(worst_rmse)) worst_rmse = rows[k].d_rmse();
      }
      if (!worst) continue;
      md += fmt::format("| {} | {:.3g} | {} | {} | {:.1f} | {:.2f} % | {} | {:.2f} % | {:.4f} | {:+.1f} % | {} {:.2f} % | {:.2f} % |\n",
                        name(worst->scene), worst->radius, worst->view, res, worst->angle_p95, 100 * worst->pos_p99_over_r,
                        worst->algorithm, 100 * worst->share, worst->mean, 100 * worst_rmse, other ? other->algorithm : "-",
                        other ? 100 * other->share : 0.0, pos ? 100 * pos->share : 0.0);
      // Only where positions alone do not already change the AO visibly: that is (a)'s business.
      if (!pos || !pos->visible()) {
        normal_points.emplace_back(worst->angle_p95, worst->visible());
        if (other) normal_points_but_sao.emplace_back(other->angle_p95, other->visible());
        auto& cfg = normal_by_config[fmt::format("{}|{}|{}", worst->scene, worst->factor, res)];
        cfg.first = std::max(cfg.first, worst->angle_p95);
        cfg.second = cfg.second || worst->visible();
      }
    }
    i = j;
  }
  for (const auto& [k, v] : pos_by_config) pos_decisions.push_back(v);
  for (const auto& [k, v] : normal_by_config) normal_decisions.push_back(v);
  md += "\n### Thresholds (x > threshold: dropped)\n\n";
  md += describe("(a) per view, x = p99 pos err / R", pos_points, 0.02, 100, " %");
  md += describe("(a) per scene and radius (the profile's decision: worst view)", pos_decisions, 0.02, 100, " %");
  md += describe("(b) per view and resolution, x = p95 angle", normal_points, 10, 1, " deg");
  md += describe("(b) per scene, radius and resolution (worst view)", normal_decisions, 10, 1, " deg");
  md += describe("(b) per view and resolution, every method but SAO", normal_points_but_sao, 10, 1, " deg");
  std::printf("%s", md.c_str());

  json j = json::array();
  for (const auto& r : rows)
    j.push_back({{"scene", r.scene}, {"view", r.view}, {"radius_factor", r.factor}, {"radius", r.radius},
                 {"variant_r16f", r.key16}, {"algorithm", r.algorithm}, {"resolution", r.resolution},
                 {"normals_from_depth", r.normals_from_depth}, {"pos_p99_over_r", r.pos_p99_over_r},
                 {"angle_p95", r.angle_p95}, {"share_over_0_1", r.share}, {"mean_abs", r.mean}, {"max_abs", r.max},
                 {"rmse_r16f", r.rmse16}, {"rmse_r32f", r.rmse32}});
  std::filesystem::create_directories(out);
  util::write_atomic(out / "r16f.json", json{{"size", fmt::format("{}x{}", size.width, size.height)}, {"rays", rays}, {"rows", j}}.dump(1) + "\n");
  util::write_atomic(out / "r16f.md", md);
  return 0;
}
