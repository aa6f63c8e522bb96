#pragma once
// The parts of generator subcommands that need the rendering modules: `analyze --gpu` (RADV) and
// `list --scene` (a scene profile). With AOVAR_WITH_RENDER they are analyze_gpu.cpp and list_scene.cpp;
// a generator-only build links without_render.cpp instead, which says in one line that they are not in it.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli/exit_code.h"
#include "cli/options.h"
#include "compile/pick_table.h"

namespace aovar::cli {

struct GpuAnalyzeArgs {
  std::string families;            // --gpu FAMILY[,FAMILY...]
  std::string out;                 // folder for gpu.json (empty: none)
  std::string size = "1920x1080";  // frame the roofline estimate is for
  CommonOptions common;
};
// An error when a family failed (its error is in the table and gpu.json); the other families' results stand.
ExitCode run_analyze_gpu(const GpuAnalyzeArgs& a);

// aovar list's options; run_list_scene reads them with --scene.
struct ListArgs {
  CommonOptions common;
  std::string scene, size = default_size;
  bool show_pruned = false, json = false;
};
// The variants the scene's profile keeps; show_pruned adds every dropped one with its reason; json: as one
// JSON document.
ExitCode run_list_scene(const ListArgs& a);

// generate --from-table: what a cost table keeps (decide/fronts.h). --for names GPU families and backends.
struct TableRequestArgs {
  std::string table;
  std::string manifest;  // what generate generates from: a table measured with another one is refused
  std::vector<std::string> targets;
  std::optional<double> budget_ms, max_error;
  std::string budget_of;
};
struct TableChoice {
  std::vector<std::string> keys;            // the variants to generate, sorted
  std::vector<compile::PickFront> fronts;   // the pick table
  variants::CalibratedValues parameters;    // what the rows were scored with (the table's meta.calibration)
  std::filesystem::path calibration;        // the file that holds them, where the table names one
  std::string summary;                      // a line per target: its front's size and ends
};
// Throws std::runtime_error, one line: an unknown family or backend in --for, a table whose meta.manifest_hash
// is not the manifest's, a table whose calibration file is not there or differs from what was scored, a target
// the table has no rows for, a pick nothing satisfies, an unreadable table.
TableChoice choose_from_table(const TableRequestArgs& a);

// generate --calibration FILE: its values checked against the manifest (calibrate/file.h), for the variants
// the globs select.
variants::CalibratedValues calibration_values(const std::string& file, const variants::Manifest& manifest);

}  // namespace aovar::cli
