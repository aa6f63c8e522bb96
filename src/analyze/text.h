#pragma once
// What `aovar analyze` prints after the per-program table (program_table).
#include <filesystem>
#include <string>

#include "analyze/analyze.h"

namespace aovar::analyze {

// "# P programs, V variants (counts per pixel, upper bounds) -> FILE": the closing line naming analysis.json.
std::string summary_line(const Analysis& a, const std::filesystem::path& written);

}  // namespace aovar::analyze
