// `aovar reference`: every selected view's reference, its files and reference.json.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "reference/reference.h"
#include "util/fs.h"
#include "util/path_names.h"
#include "util/schema.h"

namespace aovar::reference {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

std::string duration(double s) {
  auto total = static_cast<long>(std::lround(std::max(0.0, s)));
  return fmt::format("{}m{:02}s", total / 60, total % 60);
}

std::string bar(double fraction, int width = 24) {
  int filled = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * width);
  return std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.');
}

nlohmann::json view_json(const RunView& v) {
  const auto& o = v.options;
  nlohmann::json j;
  j["view"] = v.view;
  j["size"] = fmt::format("{}x{}", o.size.width, o.size.height);
  j["radius"] = o.radius;
  j["rays"] = o.rays;
  j["mode"] = mode_name(o.mode);
  j["frame"] = o.frame;
  j["mean_visibility"] = v.stats.mean_visibility;
  j["mean_std_error"] = v.stats.mean_std_error;
  j["background_share"] = v.stats.background_share;
  j["trace_s"] = v.trace_s;
  j["rays_traced"] = v.rays_traced;
  j["rays_per_s"] = v.trace_s > 0 ? static_cast<double>(v.rays_traced) / v.trace_s : 0.0;
  j["from_cache"] = v.from_cache;
  j["key"] = v.key;
  j["files"] = {{"visibility", v.files.at(0)}, {"std_error", v.files.at(1)}, {"preview", v.files.at(2)}};
  return j;
}

}  // namespace

RunResult run_reference(const RunOptions& o, const RunStatus& status) {
  const auto start = Clock::now();
  if (o.out.empty()) throw std::runtime_error("--out: give the folder for the reference images");
  scene::LoadOptions load;
  load.views_file = o.views_file;
  scene::Scene sc = scene::load_scene(o.scene, load);
  std::vector<const scene::View*> views;
  if (o.views.empty()) views.push_back(&sc.views.front());
  for (const auto& name : o.views) views.push_back(&sc.view(name));

  ReferenceOptions ro = o.reference;
  if (o.radius.empty()) {
    ro.radius = sc.ao_radius;
  } else {
    try {
      ro.radius = resolve_radius(o.radius, sc);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--radius: ") + e.what());
    }
  }
  if (ro.rays < 1) throw std::runtime_error(fmt::format("--rays {}: need at least 1 ray per pixel", ro.rays));

  RunResult res;
  res.scene = sc.name;
  res.scene_hash = sc.content_hash;
  res.triangles = sc.triangle_count();
  nlohmann::json doc;
  doc["schema_version"] = util::kSchemaVersion;
  doc["scene"] = sc.name;
  doc["scene_hash"] = sc.content_hash;
  doc["triangles"] = sc.triangle_count();
  doc["views"] = nlohmann::json::array();

  for (std::size_t i = 0; i < views.size(); ++i) {
    const scene::View& view = *views[i];
    std::string what = fmt::format("[view {}/{} {}]", i + 1, views.size(), view.name);
    auto progress = [&](double fraction, double elapsed) {
      if (!status) return;
      std::string eta = fraction > 0.005 && fraction < 1.0 ? ", ETA " + duration(elapsed * (1.0 - fraction) / fraction) : "";
      status(fmt::format("{} [{}] {:3.0f}% {}x{} x {} rays, {}{}", what, bar(fraction), 100.0 * fraction,
                         ro.size.width, ro.size.height, ro.rays, duration(elapsed), eta),
             false);
    };
    ReferenceImage ref = trace_reference(sc, view, ro, progress);

    RunView rv;
    rv.view = view.name;
    rv.options = ro;
    rv.stats = reference_stats(ref);
    rv.key = ref.key;
    rv.from_cache = ref.from_cache;
    rv.trace_s = ref.trace_s;
    rv.rays_traced = ref.rays_traced;
    rv.files = {view.name + ".pfm", view.name + ".stderr.pfm", view.name + ".png"};
    util::check_path_component(view.name, "view name");
    write_reference(o.out / view.name, ref);
    res.views.push_back(rv);
    doc["views"].push_back(view_json(rv));
    // Rewritten after every view, so that it always describes the files next to it.
    util::write_atomic(o.out / "reference.json", doc.dump(2) + "\n");

    if (status) {
      std::string how = rv.from_cache
                            ? "from the cache"
                            : fmt::format("traced in {:.1f} s ({:.2f} Mrays/s)", rv.trace_s,
                                          rv.trace_s > 0 ? static_cast<double>(rv.rays_traced) / rv.trace_s / 1e6 : 0.0);
      status(fmt::format("{}: {}x{}, {} rays, {}, radius {:.4g}: mean visibility {:.4f}, mean std error {:.4f}, "
                         "background {:.1f}%, {}",
                         view.name, ro.size.width, ro.size.height, ro.rays, mode_name(ro.mode), ro.radius,
                         rv.stats.mean_visibility, rv.stats.mean_std_error, 100.0 * rv.stats.background_share, how),
             true);
    }
  }
  res.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  return res;
}

}  // namespace aovar::reference
