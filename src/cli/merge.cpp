// aovar merge: join sweep shards (checked by their shard.json) or plain cost tables into one.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/subcommand.h"
#include "sweep/merge.h"
#include "table/table.h"
#include "util/fs.h"
#include "util/output_apart.h"

namespace aovar::cli {
namespace {

struct MergeArgs {
  std::string out;
  std::vector<std::string> inputs;
};

ExitCode run_merge(const MergeArgs& a) {
  std::vector<std::filesystem::path> in(a.inputs.begin(), a.inputs.end());
  util::check_output_apart_from_inputs(a.out, in, "merge");  // before the lock leaves a file in an input
  const auto lock = lock_output_of_file(a.out);
  auto r = sweep::merge_shards(in, a.out);
  table::write_json(r.table, a.out);
  std::cout << fmt::format("{} rows from {} {} -> {}\n", r.table.rows.size(), in.size(), r.shards ? "shards" : "tables",
                           util::display_path(a.out));
  if (!r.balance.empty()) std::cout << "balance: " << r.balance << "\n";
  return ExitCode::ok;
}

}  // namespace

Command add_merge(CLI::App& app) {
  auto [cmd, a] = subcommand<MergeArgs>(
      app, "merge",
      "join sweep shards (checked by their shard.json) or cost tables into one");
  cmd->add_option("OUT", a->out, "cost_table.json to write")->required();
  cmd->add_option("IN", a->inputs,
                  "shard output folders or their cost_table.json files (a sharded run: every shard exactly once)")
      ->required();
  return {cmd, runs(a, run_merge)};
}

}  // namespace aovar::cli
