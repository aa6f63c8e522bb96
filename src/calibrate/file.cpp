// The calibration file: writing it, and reading it back checked against the manifest it is applied with.
#include "calibrate/file.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "util/fs.h"
#include "util/hash.h"
#include "variants/key.h"
#include "util/schema.h"

namespace aovar::calibrate {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

json views_json(const std::vector<ViewCase>& list) {
  json out = json::array();
  for (const auto& v : list) out.push_back({{"scene", v.scene}, {"view", v.view}});
  return out;
}

json fit_json(const Fit& f) {
  json views = json::array();
  for (const auto& v : f.views)
    views.push_back({{"scene", v.scene}, {"view", v.view}, {"training", v.training},
                     {"rmse_before", v.rmse_before}, {"rmse_after", v.rmse_after}});
  json curve = json::array();  // best training RMSE after each evaluation
  for (double m : f.search.best_so_far) curve.push_back(std::sqrt(m));
  return {{"algorithm", f.algorithm},
          {"variant", f.variant},
          {"params", f.fitted},
          {"defaults", f.defaults},
          {"search", {{"method", f.search.method},
                      {"evaluations", f.search.evaluations},
                      {"budget", f.budget},
                      {"converged", f.search.converged},
                      {"stop", f.search.stop},
                      {"train_rmse_curve", curve}}},
          {"train_rmse_before", f.train_rmse_before},
          {"train_rmse_after", f.train_rmse_after},
          {"holdout_rmse_before", f.holdout_rmse_before},
          {"holdout_rmse_after", f.holdout_rmse_after},
          {"views", views}};
}

// One entry's parameter values, each a `fit`-able or plain parameter of `algorithm` within its range.
render::ParamOverrides checked_params(const json& params, const variants::Algorithm& algorithm,
                                      const std::string& where) {
  render::ParamOverrides out;
  for (auto& [key, value] : params.items()) {
    const std::string name = key.rfind("ao.", 0) == 0 ? key.substr(3) : std::string();
    auto p = std::find_if(algorithm.params.begin(), algorithm.params.end(),
                          [&](const auto& q) { return q.name == name; });
    if (p == algorithm.params.end())
      throw std::runtime_error(fmt::format("{}: '{}' is not a parameter of the manifest's {} (a calibration for another "
                                           "manifest? refit with aovar calibrate)",
                                           where, key, algorithm.name));
    if (!value.is_number()) throw std::runtime_error(fmt::format("{}: '{}' must be a number", where, key));
    const double v = value.get<double>();
    if (!(v >= p->min && v <= p->max))
      throw std::runtime_error(fmt::format("{}: {} = {} is outside the manifest's range [{}, {}] (refit with aovar "
                                           "calibrate, or widen the range in the manifest)",
                                           where, key, v, p->min, p->max));
    out[key] = v;
  }
  return out;
}

}  // namespace

void write_calibration(const fs::path& path, const Calibration& cal) {
  json algorithms = json::object(), variants = json::object();
  for (const auto& f : cal.fits) (f.per_variant ? variants[f.variant] : algorithms[f.algorithm]) = fit_json(f);
  json doc = {{"schema_version", util::kSchemaVersion},
              {"tool", "aovar calibrate"},
              {"backend", cal.backend},
              {"size", fmt::format("{}x{}", cal.size.width, cal.size.height)},
              {"rays", cal.rays},
              {"mode", reference::mode_name(cal.mode)},
              {"training", views_json(cal.views.training)},
              {"holdout", views_json(cal.views.holdout)},
              {"algorithms", algorithms},
              {"variants", variants}};
  util::write_atomic(path, doc.dump(2) + "\n");
}

variants::CalibratedValues load_calibration(const fs::path& path, const variants::Manifest& manifest) {
  const std::string display = util::display_path(path);
  auto text = util::read_file(path);
  if (!text) throw std::runtime_error(fmt::format("{}: error: cannot read the calibration file", display));
  json doc;
  try {
    doc = json::parse(*text);
    if (!doc.is_object() || !doc.contains("algorithms") || !doc.at("algorithms").is_object())
      throw std::runtime_error("no \"algorithms\" object");
    util::check_schema(doc, path);
  } catch (const util::NewerSchema&) {
    throw;  // already names the file and what to do
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("{}: error: not a calibration file ({}); write one with aovar calibrate", display, e.what()));
  }
  variants::CalibratedValues out;
  try {
    for (auto& [name, entry] : doc.at("algorithms").items()) {
      const variants::Algorithm* a = manifest.algorithm(name);
      const std::string where = fmt::format("{}: error: algorithms.{}", display, name);
      if (!a) throw std::runtime_error(fmt::format("{}: the manifest has no algorithm '{}'", where, name));
      out[name] = checked_params(entry.at("params"), *a, where);
    }
    if (doc.contains("variants"))
      for (auto& [key, entry] : doc.at("variants").items()) {
        const std::string where = fmt::format("{}: error: variants.{}", display, key);
        auto point = variants::parse_key(manifest, key);
        if (!point) throw std::runtime_error(fmt::format("{}: not a variant key of the manifest", where));
        const auto& algorithm = manifest.value(variants::Axis::algorithm, (*point)[variants::index(variants::Axis::algorithm)]);
        out[key] = checked_params(entry.at("params"), *manifest.algorithm(algorithm.text), where);
      }
  } catch (const json::exception& e) {
    throw std::runtime_error(
        fmt::format("{}: error: not a calibration file ({}); write one with aovar calibrate", display, e.what()));
  }
  return out;
}

table::CalibrationRef calibration_source(const fs::path& path) {
  if (path.empty()) return {};
  auto text = util::read_file(path);
  if (!text) throw std::runtime_error(fmt::format("{}: error: cannot read the calibration file", util::display_path(path)));
  return {util::display_path(path), util::hash_hex(*text), {}};
}

table::CalibrationRef read_calibration(const fs::path& path, const variants::Manifest& manifest) {
  if (path.empty()) return {};
  table::CalibrationRef c = calibration_source(path);
  c.values = load_calibration(path, manifest);
  return c;
}

std::string measured_with(const std::optional<table::CalibrationRef>& used, const table::CalibrationRef& expected,
                          const std::string& table) {
  if (used && used->hash == expected.hash) return "";
  if (!used && expected.hash.empty()) return "";
  const std::string what = used ? fmt::format("{} (hash {})", used->file.empty() ? "?" : used->file, used->hash.substr(0, 12))
                                : "no calibration file recorded";
  return fmt::format("{}: error: measured with {}, not {} (hash {}); measure again with --calibration {}", table, what,
                     expected.file, expected.hash.substr(0, 12), expected.file);
}

}  // namespace aovar::calibrate
