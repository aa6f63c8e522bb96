#include "calibrate/text.h"

#include <cmath>

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::calibrate {
namespace {

// The convergence curve in a few points: the lowest root mean training MSE after 1, 25 %, 50 %, 75 % and all evaluations.
std::string curve_text(const Minimum& m) {
  const auto& c = m.best_so_far;
  if (c.empty()) return "";
  std::string s;
  std::size_t last = 0;
  for (double share : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    std::size_t i = std::min(c.size() - 1, static_cast<std::size_t>(share * static_cast<double>(c.size() - 1) + 0.5));
    if (!s.empty() && i == last) continue;
    s += fmt::format("{}{}: {:.4f}", s.empty() ? "" : ", ", i + 1, std::sqrt(c[i]));
    last = i;
  }
  return s;
}

}  // namespace

// The fits (train and held-out error before -> after, fitted values with the defaults, the search and
// how it converged) and the closing line.
std::string to_text(const Calibration& c, const std::filesystem::path& out) {
  std::string s = fmt::format("{:<10} {:>11} {:>17} {:>17}  {}\n", "fit", "evaluations", "train rmse", "held-out rmse",
                              "fitted (default)");
  for (const auto& f : c.fits) {
    std::string values;
    for (const auto& [key, value] : f.fitted) values += fmt::format("{} {:.4g} ({:.4g})  ", key, value, f.defaults.at(key));
    s += fmt::format("{:<10} {:>5} / {:<3} {:>7.4f} -> {:>6.4f} {:>7.4f} -> {:>6.4f}  {}\n", f.per_variant ? f.variant : f.algorithm,
                     f.search.evaluations, f.budget, f.train_rmse_before, f.train_rmse_after, f.holdout_rmse_before,
                     f.holdout_rmse_after, values);
    s += fmt::format("{:<10} {} {} ({}); training error (root of the mean MSE) by evaluation: {}\n", "", f.search.method,
                     f.search.converged ? "converged" : "stopped at its budget", f.search.stop, curve_text(f.search));
  }
  std::string scenes;
  for (const auto& v : c.views.training)
    if (scenes.find(v.scene) == std::string::npos) scenes += (scenes.empty() ? "" : ", ") + v.scene;
  return s + fmt::format("# {} at {}x{}, references {} rays ({}); {} training and {} held-out views of {}; -> {}\n",
                         c.backend, c.size.width, c.size.height, c.rays, reference::mode_name(c.mode),
                         c.views.training.size(), c.views.holdout.size(), scenes, util::display_path(out));
}

}  // namespace aovar::calibrate
