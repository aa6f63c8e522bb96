#pragma once
// The subcommands of aovar, one file each (src/cli/<name>.cpp): add_<name> registers the subcommand and
// its options on the app and returns it with the function that runs it once the command line is parsed.
#include <CLI/CLI.hpp>

#include <functional>

#include "cli/exit_code.h"

namespace aovar::cli {

struct Command {
  CLI::App* app;             // the subcommand: app->parsed() when it was given
  std::function<ExitCode()> run;  // ok or check_failed; throws std::exception for errors (see run_guarded)
};

Command add_list(CLI::App& app);
Command add_profile(CLI::App& app);
Command add_generate(CLI::App& app);
Command add_measure(CLI::App& app);
Command add_calibrate(CLI::App& app);
Command add_reference(CLI::App& app);
Command add_analyze(CLI::App& app);
Command add_select(CLI::App& app);
Command add_diff(CLI::App& app);
Command add_merge(CLI::App& app);
Command add_report(CLI::App& app);
Command add_stress(CLI::App& app);
Command add_sweep(CLI::App& app);
Command add_ship(CLI::App& app);
Command add_gbuffer(CLI::App& app);

}  // namespace aovar::cli
