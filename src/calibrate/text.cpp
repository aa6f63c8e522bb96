#include "calibrate/text.h"

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::calibrate {

// The fits (train and validation error before -> after, fitted values with the defaults) and the closing line.
std::string to_text(const Calibration& c, const std::filesystem::path& out) {
  std::string s = fmt::format("{:<10} {:>6} {:>17} {:>19}  {}\n", "algorithm", "evals", "train rmse", "validation rmse",
                              "fitted (default)");
  for (const auto& f : c.fits) {
    std::string values;
    for (const auto& [key, value] : f.fitted) values += fmt::format("{} {:.4g} ({:.4g})  ", key, value, f.defaults.at(key));
    s += fmt::format("{:<10} {:>6} {:>7.4f} -> {:>6.4f} {:>8.4f} -> {:>6.4f}  {}\n", f.algorithm, f.evaluations,
                     f.train_rmse_before, f.train_rmse_after, f.validation_rmse_before, f.validation_rmse_after, values);
  }
  return s + fmt::format("# {} at {}x{}, references {} rays ({}); -> {}\n", c.backend, c.size.width, c.size.height,
                         c.rays, reference::mode_name(c.mode), util::display_path(out));
}

}  // namespace aovar::calibrate
