#pragma once
// A measurement for people: the rows as a table, then the "# ..." notes (devices, scene and counts, pruning,
// calibration, contact sheets). What `aovar measure` prints.
#include <filesystem>
#include <string>

#include "measure/measure.h"

namespace aovar::measure {

// One line per variant, view and backend: times, rel, error (with --reference) and per-pass minima; then
// where_text.
std::string to_text(const MeasureResult& result);
// With --reference, "where the error comes from:" and per row its breakdown's figures and reading ("" without).
std::string where_text(const MeasureResult& result);

// `calibration_file`: the calibration applied (empty: none).
std::string notes_text(const MeasureResult& result, const MeasureOptions& options,
                       const std::filesystem::path& calibration_file);

}  // namespace aovar::measure
