// aovar report: report.md and a self-contained report.html from a cost table (a sweep's, a merged one, an
// edited one).
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <stdexcept>
#include <system_error>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/subcommand.h"
#include "report/report.h"
#include "table/table.h"
#include "util/fs.h"
#include "variants/manifest.h"

namespace aovar::cli {
namespace {

struct ReportArgs {
  std::string table, out, manifest = default_manifest;
  bool manifest_given = false;
};

// The methods' colours and display names: the manifest's. Without --manifest, the default one where it exists:
// a table is also reported away from a checkout, its methods then grey.
report::Methods methods_of(const ReportArgs& a) {
  if (!a.manifest_given && !std::filesystem::exists(a.manifest)) return {};
  return variants::load_manifest(a.manifest).algorithms;
}

ExitCode run_report(const ReportArgs& a) {
  const report::Methods methods = methods_of(a);
  auto t = table::read_table(a.table);
  std::filesystem::path images = std::filesystem::path(a.table).parent_path();
  std::filesystem::path dir = a.out.empty() ? images : std::filesystem::path(a.out);
  if (images.empty()) images = ".";
  if (dir.empty()) dir = ".";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(util::display_path(dir) + ": error: cannot create the output folder: " + ec.message());
  const auto lock = lock_output(dir);
  const std::size_t rows = t.rows.size();
  report::write_reports(std::move(t), dir, images, methods);
  std::cout << fmt::format("{} rows -> {} and {}\n", rows, util::display_path(dir / "report.md"),
                           util::display_path(dir / "report.html"));
  return ExitCode::ok;
}

}  // namespace

Command add_report(CLI::App& app) {
  auto [cmd, a] = subcommand<ReportArgs>(app, "report", "report.md and a self-contained report.html from a cost table");
  cmd->add_option("--table,-t", a->table, "cost_table.json (image paths are relative to its folder)")->required();
  cmd->add_option("--out,-o", a->out, "output folder (default: the table's folder)");
  add_manifest(cmd, a->manifest);  // the methods' colours ([algorithms.*] color)
  CLI::Option* manifest = cmd->get_option("--manifest");
  return {cmd, runs(a, [manifest](ReportArgs& args) {
            args.manifest_given = manifest->count() > 0;
            return run_report(args);
          })};
}

}  // namespace aovar::cli
