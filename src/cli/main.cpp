// aovar: the command line. Each subcommand lives in its own file (src/cli/<name>.cpp) as a thin layer over
// the libraries; the option helpers they share are in src/cli/options.h. This file builds the app,
// registers the subcommands (in the order --help lists them) and runs the one given.
#include <CLI/CLI.hpp>

#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/exit_code.h"
#include "cli/options.h"
#include "compile/glslang_compiler.h"

int main(int argc, char** argv) {
  using namespace aovar::cli;
  CLI::App app{"aovar: generate, validate and measure SSAO shader variants"};
  app.footer("Exit status: 0 success; 1 the check asked for failed (select found no variant, stress found a failure, "
             "generate --check found stale output); 2 error (usage or runtime).");
  app.require_subcommand(1);
  app.set_version_flag("--version", aovar::compile::tool_version());
  const std::vector<Command> commands = {
      add_list(app),      add_profile(app), add_generate(app), add_measure(app), add_calibrate(app),
      add_reference(app), add_analyze(app), add_select(app),   add_diff(app),    add_merge(app),
      add_report(app),    add_stress(app),  add_sweep(app),    add_ship(app),
      add_gbuffer(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints help or the version (its code 0); a usage error is one line naming the command that was
    // run and the option (CLI11's own text would add a second line).
    if (e.get_exit_code() == 0) return app.exit(e) == 0 ? exit_status(ExitCode::ok) : exit_status(ExitCode::error);
    std::cerr << usage_error_line(commands, e.what()) << "\n";
    return exit_status(ExitCode::error);
  }
  for (const auto& c : commands)
    if (c.app->parsed()) return exit_status(run_guarded(c.run, c.app->get_name()));
  return exit_status(ExitCode::error);  // not reached: require_subcommand(1) makes the parse fail without one
}
