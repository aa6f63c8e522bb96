#pragma once
// The calibration file: JSON, written atomically by `aovar calibrate`, read by measure, sweep and stress.
// Its contract is in docs/cli.md ("calibration.json").
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "calibrate/calibrate.h"
#include "render/plan.h"
#include "table/sweep_meta.h"
#include "variants/manifest.h"

namespace aovar::calibrate {

void write_calibration(const std::filesystem::path& path, const Calibration& calibration);

// The parameter values to apply, by algorithm name and by variant key (a variant's entry wins over its
// algorithm's; render plans look them up in that order). Every value is checked against the manifest: a
// file for another manifest or hand-edited past a parameter's range is refused, with a one-line
// std::runtime_error "<file>: error: <entry>: ..." that says what to do. Unreadable or malformed files too.
variants::CalibratedValues load_calibration(const std::filesystem::path& path, const variants::Manifest& manifest);

// The calibration file at `path` as a table records it: its display path and the hash of its bytes (both empty for
// an empty path: none, the manifest's defaults).
table::CalibrationRef calibration_source(const std::filesystem::path& path);

// Both: where the file is, the hash of its bytes and its checked values (empty for an empty path: none).
table::CalibrationRef read_calibration(const std::filesystem::path& path, const variants::Manifest& manifest);

// Whether a table (or measure.json) that recorded `used` (nullopt: no calibration file) was measured with
// `expected`: empty when it was, else the one-line reason ("<table>: error: measured with <file> (hash ...), not
// <file>; ...").
std::string measured_with(const std::optional<table::CalibrationRef>& used, const table::CalibrationRef& expected,
                          const std::string& table);

}  // namespace aovar::calibrate
