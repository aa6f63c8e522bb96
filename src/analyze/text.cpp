#include "analyze/text.h"

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::analyze {

std::string summary_line(const Analysis& a, const std::filesystem::path& written) {
  return fmt::format("# {} programs, {} variants (counts per pixel, upper bounds) -> {}\n", a.programs.size(),
                     a.variants.size(), util::display_path(written));
}

}  // namespace aovar::analyze
