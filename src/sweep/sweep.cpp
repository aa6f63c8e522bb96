#include "sweep/sweep.h"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::sweep {
namespace fs = std::filesystem;
using json = nlohmann::json;

std::string scene_folder(const std::string& scene) {
  std::string out;
  if (scene.rfind("builtin:", 0) == 0) {
    out = "builtin_" + scene.substr(8);
  } else {
    out = fs::path(scene).stem().string() + "-" + util::hash_hex(scene).substr(0, 8);
  }
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return out;
}

SweepResult run_sweep(const SweepOptions& o, const std::function<void(const std::string&)>& progress) {
  auto start = std::chrono::steady_clock::now();
  if (o.out.empty()) throw std::runtime_error("sweep: --out is required");
  if (o.scenes.empty()) throw std::runtime_error("sweep: give at least one --scene");
  SweepResult res;
  json scenes = json::array();
  for (std::size_t i = 0; i < o.scenes.size(); ++i) {
    measure::MeasureOptions mo = o.measure;
    mo.scene = o.scenes[i];
    mo.ground_truth = true;
    mo.out = o.out / "measure" / scene_folder(o.scenes[i]);
    if (mo.views.empty()) {  // every view of the scene: the Pareto front per view and for the worst view
      scene::LoadOptions lo;
      lo.views_file = mo.views_file;
      for (const auto& v : scene::load_scene(mo.scene, lo).views) mo.views.push_back(v.name);
    }
    auto where = fmt::format("scene {}/{} {}", i + 1, o.scenes.size(), o.scenes[i]);
    auto r = measure::run_measure(mo, [&](const std::string& line) {
      if (progress) progress(line.rfind("note: ", 0) == 0 ? line : where + ": " + line);
    });
    res.rows_reused += r.reused;
    res.rows_measured += static_cast<int>(r.rows.size()) - r.reused;
    if (r.rows.empty()) continue;  // a shard holding none of the variants
    auto text = util::read_file(mo.out / "measure.json");
    if (!text) throw std::runtime_error(util::display_path(mo.out / "measure.json") + ": error: missing after measuring");
    json m = json::parse(*text);
    // A baseline measured only for timing (not selected) is not a row of the table: another shard owns it.
    json kept = json::array();
    for (const auto& row : m.at("rows"))
      if (!row.value("is_baseline", false)) kept.push_back(row);
    m["rows"] = kept;
    auto t = table::from_measure(m);
    for (auto& row : t.rows) {
      for (auto& image : row.images) image = (fs::path("measure") / scene_folder(o.scenes[i]) / image).generic_string();
      res.table.rows.push_back(std::move(row));
    }
    scenes.push_back({{"scene", o.scenes[i]}, {"measure", (fs::path("measure") / scene_folder(o.scenes[i]) / "measure.json").generic_string()},
                      {"hash", r.scene_hash}, {"radius", r.radius}});
  }
  table::mark_pareto(res.table);
  res.table.meta = {{"tool", "aovar sweep"},
                    {"manifest", util::display_path(o.measure.manifest)},
                    {"scenes", scenes},
                    {"backends", o.measure.backends},
                    {"size", fmt::format("{}x{}", o.measure.size.width, o.measure.size.height)},
                    {"reps", o.measure.reps},
                    {"rays", o.measure.reference_rays},
                    {"calibrated", !o.measure.calibration.empty()},
                    {"shard", fmt::format("{}/{}", o.measure.shard_index + 1, o.measure.shard_count)}};
  table::write_table_files(res.table, o.out);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace aovar::sweep
