// aovar analyze: static cost per program and variant of a generated folder (SPIR-V) -> analysis.json.
#include <iostream>
#include <memory>

#include "analyze/analyze.h"
#include "analyze/text.h"
#include "cli/commands.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

int run_analyze(const std::string& dir) {
  auto a = analyze::analyze_folder(dir);
  std::cout << analyze::program_table(a);
  auto out = std::filesystem::path(dir) / "analysis.json";
  util::write_if_changed(out, analyze::analysis_json(a));
  std::cout << analyze::summary_line(a, out);
  return 0;
}

}  // namespace

Command add_analyze(CLI::App& app) {
  auto in = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("analyze", "static cost per program and variant of a generated folder (SPIR-V)");
  cmd->add_option("--in", *in, "folder written by `aovar generate --emit index,spirv`")->required();
  return {cmd, [in] { return run_analyze(*in); }};
}

}  // namespace aovar::cli
