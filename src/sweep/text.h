#pragma once
// The "# ..." lines `aovar sweep` prints after the cost table: cost models, pruning, profiles, counts, report.
#include <filesystem>
#include <string>

#include "sweep/sweep.h"

namespace aovar::sweep {

// `calibration_file`: the calibration applied (empty: none).
std::string notes_text(const SweepResult& result, const SweepOptions& options,
                       const std::filesystem::path& calibration_file);

}  // namespace aovar::sweep
