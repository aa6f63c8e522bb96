#pragma once
// Reports a person reads (docs/cli.md, "File formats"): report.md and a self-contained report.html (no network: inline
// SVG charts, images embedded as data URIs) from a cost table — the Pareto front per scene/view/backend,
// Pareto scatter coloured by algorithm, time per variant, static cost against measured time, an image grid
// (variant, reference, error heat map) for the front, where the front's error comes from
// (error_sources.h), and the Sunet 2018 pairs measured on these scenes.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "report/seed_pairs.h"
#include "table/table.h"
#include "variants/manifest.h"

namespace aovar::report {

// The methods as the manifest describes them ([algorithms.*]: colour, display name). The charts colour each
// row by its method's entry; a method the list lacks (a table from another manifest, or no manifest) is
// drawn grey under its name.
using Methods = std::vector<variants::Algorithm>;

std::string markdown_report(const table::CostTable& table);
// `dir`: the folder the table's image paths are relative to (the sweep's output folder).
std::string html_report(const table::CostTable& table, const std::filesystem::path& dir, const Methods& methods = {});

// DIR/report.md and DIR/report.html, atomically; the table's image paths are relative to `images_dir`
// (default: DIR, where `aovar sweep` writes both).
void write_reports(const table::CostTable& table, const std::filesystem::path& dir, const Methods& methods = {});
void write_reports(const table::CostTable& table, const std::filesystem::path& dir, const std::filesystem::path& images_dir,
                   const Methods& methods = {});
// The same for a table the caller no longer needs: its front is marked in place instead of on a copy (a
// 1,000,000-row table is gigabytes; `aovar report`).
void write_reports(table::CostTable&& table, const std::filesystem::path& dir, const std::filesystem::path& images_dir,
                   const Methods& methods = {});

}  // namespace aovar::report
