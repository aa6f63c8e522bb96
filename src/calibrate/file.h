#pragma once
// The calibration file: JSON, written atomically by `aovar calibrate`, read by measure, sweep and stress.
// Its contract is in docs/cli.md ("calibration.json").
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "calibrate/calibrate.h"
#include "render/plan.h"
#include "variants/manifest.h"

namespace aovar::calibrate {

void write_calibration(const std::filesystem::path& path, const Calibration& calibration);

// The parameter values to apply, by algorithm name and by variant key (a variant's entry wins over its
// algorithm's; render plans look them up in that order). Every value is checked against the manifest: a
// file for another manifest or hand-edited past a parameter's range is refused, with a one-line
// std::runtime_error "<file>: error: <entry>: ..." that says what to do. Unreadable or malformed files too.
std::map<std::string, render::ParamOverrides> load_calibration(const std::filesystem::path& path,
                                                               const variants::Manifest& manifest);

// What a table or measure.json records about the calibration it was measured with.
struct CalibrationSource {
  std::string file;  // display path; empty: none (the manifest's defaults)
  std::string hash;  // of the file's bytes
  bool operator==(const CalibrationSource&) const = default;
};
CalibrationSource calibration_source(const std::filesystem::path& path);  // empty path: none

// Whether a table (or measure.json) whose meta is `meta` was measured with `expected`: empty when it was,
// else the one-line reason ("<table> was measured with <file> (hash ...), not <file>; ...").
std::string measured_with(const nlohmann::json& meta, const CalibrationSource& expected, const std::string& table);

}  // namespace aovar::calibrate
