#include "cli/whole_space.h"

#include <fmt/format.h>

#include <stdexcept>

#include "variants/manifest.h"
#include "variants/space.h"

namespace aovar::cli {

void add_all(CLI::App* cmd, bool& all) {
  cmd->add_flag("--all", all,
                fmt::format("without --variants: run every variant the manifest keeps (refused above {} variants "
                            "unless given: hours of work)",
                            kMostUnselected));
}

void check_whole_space(const compile::ManifestSource& manifest, const std::vector<std::string>& globs, bool all,
                       const RunShape& shape) {
  if (all || !globs.empty()) return;
  std::size_t count = 0;
  try {
    count = variants::build_space(manifest.get()).variants.size();
  } catch (const std::exception&) {
    return;  // the run meets the manifest error and reports it in its own words
  }
  if (count <= kMostUnselected) return;
  const double minutes = static_cast<double>(count) * static_cast<double>(shape.views_per_variant) *
                         kSecondsPerVariantView / static_cast<double>(shape.shards) / 60.0;
  const std::string time = minutes < 90 ? fmt::format("{:.0f} min", minutes) : fmt::format("{:.0f} h", minutes / 60);
  throw std::runtime_error(fmt::format(
      "{}: no --variants selects all {} variants of {}: about {} ({} view(s) each, {} s a view at 640x360 on 2 "
      "cores, bench/shards); give --variants GLOB (scripts/default_selection holds the default sweep's) or --all "
      "to run them all",
      shape.command, count, manifest.path().string(), time, shape.views_per_variant, kSecondsPerVariantView));
}

}  // namespace aovar::cli
