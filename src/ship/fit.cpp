#include "ship/fit.h"

#include <filesystem>
#include <iostream>
#include <stdexcept>

#include <fmt/format.h>

#include "calibrate/file.h"
#include "ship/shards.h"
#include "util/fs.h"
#include "util/hash.h"
#include "util/text.h"

namespace aovar::ship {
namespace fs = std::filesystem;

namespace {

// What the calibration depends on: when OUT/ship.json recorded the same, OUT/calibration.json is reused.
std::string fit_inputs(const ShipOptions& o, const scene::Scene& sc, const calibrate::ViewSplit& split,
                       const std::string& normals) {
  util::Hasher h;
  h.add(o.scope.manifest->text).add(sc.content_hash).add(normals).add(o.backend);
  for (const auto* group : {&split.training, &split.holdout})
    for (const auto& v : *group) h.add(v.view).add(uint64_t(group == &split.training));
  for (const auto& v : sc.views)
    h.add(fmt::format("{} {} {} {} {} {} {} {}", v.name, v.eye.x, v.eye.y, v.eye.z, v.target.x, v.target.y, v.target.z, v.fov_y_deg));
  h.add(uint64_t(o.fit_size.width)).add(uint64_t(o.fit_size.height)).add(uint64_t(o.fit_evaluations)).add(uint64_t(o.rays));
  return h.hex();
}

// Whether OUT/calibration.json can be reused: the fit of these inputs, its text the one ship.json's checksum
// records (shards.h, fit_problem), and within the manifest's ranges. A damaged one (edited, a truncated write, a
// bad join of an earlier version) is fitted again with a warning, as damaged profiles and round tables are
// recomputed: it never blocks a resume and never changes an answer. A fit of other inputs is refitted quietly.
bool usable_fit(const fs::path& out, const std::string& inputs, const variants::Manifest& manifest) {
  const fs::path file = out / "calibration.json";
  if (!fs::exists(file) || recorded_input(out, "fit_inputs") != inputs) return false;
  try {
    if (const std::string why = fit_problem(out, inputs); !why.empty()) throw std::runtime_error(why);
    calibrate::load_calibration(file, manifest);
    return true;
  } catch (const std::exception& e) {
    std::cerr << "aovar: warning: " << util::one_line(e.what()) << " (a damaged fit: fitting again)\n";
    return false;
  }
}

}  // namespace

Fitted fit_methods(const ShipOptions& o, const scene::Scene& sc, const calibrate::ViewSplit& split,
                   const std::string& normals, const variants::Manifest& manifest, const Progress& progress) {
  const fs::path file = o.out / "calibration.json";
  const std::string inputs = fit_inputs(o, sc, split, normals);
  Fitted f;
  f.inputs = inputs;
  f.reused = usable_fit(o.out, inputs, manifest);
  if (!f.reused && !o.join.empty()) {  // the shards fitted the same inputs: take theirs
    adopt_shard_fit(o.join, inputs, o.out, manifest);
    f.reused = true;
  }
  if (!f.reused) {
    calibrate::CalibrateOptions co;
    co.scope = o.scope;
    co.fit_normals = normals;
    co.backend = o.backend;
    co.size = o.fit_size;
    co.rays = o.rays;
    co.views = split;
    co.views_file = o.views_file;
    co.budget.max_evaluations = o.fit_evaluations;
    calibrate::write_calibration(file, calibrate::calibrate(co, [&](const std::string& line) {
                                   if (progress) progress("fit: " + line);
                                 }));
    record_fit(o.out, inputs);
  }
  f.calibration = calibrate::read_calibration(file, manifest);
  return f;
}

}  // namespace aovar::ship
