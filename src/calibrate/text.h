#pragma once
// A calibration for people: per fit the train and held-out error before -> after and the fitted
// values with their defaults, then the closing line. What `aovar calibrate` prints.
#include <filesystem>
#include <string>

#include "calibrate/calibrate.h"

namespace aovar::calibrate {

// `out`: where the calibration file was written.
std::string to_text(const Calibration& calibration, const std::filesystem::path& out);

}  // namespace aovar::calibrate
