#pragma once
// Reports a person reads (docs/cli.md, "File formats"): report.md and a self-contained report.html (no network: inline
// SVG charts, images embedded as data URIs) from a cost table — the Pareto front per scene/view/backend,
// Pareto scatter coloured by algorithm, time per variant, static cost against measured time, an image grid
// (variant, reference, error heat map) for the front, and the Sunet 2018 pairs measured on these scenes.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "table/table.h"

namespace aovar::report {

// One of the pairs Sunet 2018 studied (RG vs RGB normals, depth vs position buffer, ...), measured on the
// table's rows that differ only in that axis (same scene, view, backend and every other axis).
struct PairFinding {
  std::string title, axis, a, b;      // e.g. "RG vs RGB normals", "normals", "rgb8", "rg8"
  std::string seed;                   // the seed's own finding, with its section
  int pairs = 0;                      // matched row pairs
  double time_delta_pct = 0;          // median of (time_b - time_a) / time_a, percent
  double rmse_delta = 0;              // median of rmse_b - rmse_a
};
// A row's time for a comparison; NaN or <= 0 leaves the row out. The default: the measured decision time.
using TimeOf = std::function<double(const table::CostRow&)>;
double measured_time(const table::CostRow& row);  // time_ms.decision(); NaN for predicted rows
std::vector<PairFinding> seed_pairs(const table::CostTable& table, const TimeOf& time_of = measured_time);

std::string markdown_report(const table::CostTable& table);
// `dir`: the folder the table's image paths are relative to (the sweep's output folder).
std::string html_report(const table::CostTable& table, const std::filesystem::path& dir);

// DIR/report.md and DIR/report.html, atomically; the table's image paths are relative to `images_dir`
// (default: DIR, where `aovar sweep` writes both).
void write_reports(const table::CostTable& table, const std::filesystem::path& dir);
void write_reports(const table::CostTable& table, const std::filesystem::path& dir, const std::filesystem::path& images_dir);

}  // namespace aovar::report
