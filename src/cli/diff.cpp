// aovar diff: per-variant deltas between two cost tables (helped / hurt / inconclusive); --json: as one JSON
// document with every row's verdict. Exit 0 whatever changed: diff reports, it checks nothing.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/subcommand.h"
#include "decide/diff.h"
#include "table/table.h"

namespace aovar::cli {
namespace {

struct DiffArgs {
  std::string a, b;
  bool json = false;
};

ExitCode run_diff(const DiffArgs& args) {
  auto d = decide::diff_tables(table::read_table(args.a), table::read_table(args.b));
  if (args.json) std::cout << decide::to_json(d, args.a, args.b).dump(1) << "\n";
  else std::cout << decide::format_diff(d, args.a, args.b);
  return ExitCode::ok;
}

}  // namespace

Command add_diff(CLI::App& app) {
  auto [cmd, a] = subcommand<DiffArgs>(
      app, "diff",
      "per-variant deltas between two cost tables (helped / hurt beyond the noise, inconclusive)");
  cmd->add_option("A", a->a, "the old cost_table.json")->required();
  cmd->add_option("B", a->b, "the new cost_table.json")->required();
  add_json(cmd, a->json);
  return {cmd, runs(a, run_diff)};
}

}  // namespace aovar::cli
