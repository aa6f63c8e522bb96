#pragma once
// What every add_<name> (cli/commands.h) does first and last: make the subcommand with its arguments object,
// and hand main() the function that runs on the parsed arguments. CLI11 fills the arguments while parsing
// and the run function reads them afterwards, so both hold them (a shared_ptr).
#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <utility>

#include "cli/commands.h"

namespace aovar::cli {

template <class Args>
struct NewSubcommand {
  CLI::App* cmd;
  std::shared_ptr<Args> args;
};

template <class Args>
NewSubcommand<Args> subcommand(CLI::App& parent, std::string name, std::string description) {
  return {parent.add_subcommand(std::move(name), std::move(description)), std::make_shared<Args>()};
}

// run(*args) once the command line is parsed; `run` takes the arguments object (and may capture more).
template <class Args, class Run>
std::function<ExitCode()> runs(std::shared_ptr<Args> args, Run run) {
  return [args = std::move(args), run = std::move(run)] { return run(*args); };
}

}  // namespace aovar::cli
