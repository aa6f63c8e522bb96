// aovar list: the variants after rules and the counts; with --scene only those the scene's profile keeps;
// --json: the same as one JSON document.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/render_parts.h"
#include "cli/subcommand.h"
#include "compile/list_json.h"
#include "compile/text.h"

namespace aovar::cli {
namespace {

ExitCode run_list(const ListArgs& a) {
  auto c = compile::compile_space(compile_options(a.common));
  if (!report_diagnostics(c)) return ExitCode::error;  // the diagnostics are printed
  if (a.json) std::cout << compile::list_json(c, a.show_pruned).dump(1) << "\n";
  else std::cout << compile::list_text(c, a.show_pruned);
  return ExitCode::ok;
}

}  // namespace

Command add_list(CLI::App& app) {
  auto [cmd, a] = subcommand<ListArgs>(app, "list", "print the variants after rules (one key a line) and the counts");
  add_common(cmd, a->common);
  cmd->add_flag("--pruned", a->show_pruned, "also print every dropped variant with the rule's reason");
  cmd->add_option("--scene,-s", a->scene,
                  "keep only what this scene needs (aovar profile); --pruned prints each drop's reason");
  cmd->add_option("--size", a->size, "frame size the scene is profiled at")->capture_default_str();
  add_json(cmd, a->json);
  return {cmd, runs(a, [cmd](const ListArgs& args) {
            return cmd->count("--scene") ? run_list_scene(args) : run_list(args);
          })};
}

}  // namespace aovar::cli
