// aovar merge: join shard cost tables into one (refuses conflicting duplicate rows).
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "table/compare.h"
#include "table/table.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct MergeArgs {
  std::string out;
  std::vector<std::string> inputs;
};

ExitCode run_merge(const MergeArgs& a) {
  std::vector<std::filesystem::path> in(a.inputs.begin(), a.inputs.end());
  auto t = table::merge_tables(in);
  table::write_json(t, a.out);
  std::cout << fmt::format("{} rows from {} tables -> {}\n", t.rows.size(), in.size(), util::display_path(a.out));
  return ExitCode::ok;
}

}  // namespace

Command add_merge(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  auto* cmd = app.add_subcommand("merge", "join shard cost tables into one (refuses conflicting duplicate rows)");
  cmd->add_option("OUT", a->out, "cost_table.json to write")->required();
  cmd->add_option("IN", a->inputs, "shard cost_table.json files")->required();
  return {cmd, [a] { return run_merge(*a); }};
}

}  // namespace aovar::cli
