// aovar select: the variant to ship under a time budget or an error target, with the reason, the
// runners-up and the margin (--json: as one JSON document); exit 1 when nothing satisfies.
#include <iostream>
#include <memory>

#include "calibrate/file.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/subcommand.h"
#include "decide/select.h"
#include "table/table.h"

namespace aovar::cli {
namespace {

struct SelectArgs {
  std::string table, calibration;
  decide::SelectQuery query;
  bool json = false;
};

ExitCode run_select(const SelectArgs& a) {
  const auto t = table::read_table(a.table);
  if (!a.calibration.empty())
    if (auto why = calibrate::measured_with(t.meta.calibration.value_or(std::nullopt), calibrate::calibration_source(a.calibration), a.table); !why.empty())
      throw std::runtime_error(why);
  auto sel = decide::select(t, a.query);
  if (a.json) std::cout << decide::to_json(sel).dump(1) << "\n";  // a script reads ok (or the exit status)
  else (sel.ok ? std::cout : std::cerr) << sel.text;
  return sel.ok ? ExitCode::ok : ExitCode::check_failed;
}

}  // namespace

Command add_select(CLI::App& app) {
  auto [cmd, a] = subcommand<SelectArgs>(
      app, "select",
      "the variant to ship under a time budget or an error target, with the "
      "reason, the runners-up and the margin");
  auto& q = a->query;
  cmd->add_option("--table,-t", a->table, "cost_table.json")->required();
  auto* budget = cmd->add_option("--budget-ms", q.budget_ms, "lowest error with time (time_ms.paired, else min) <= this")
                     ->check(finite_number(0, true));
  auto* budget_of = cmd->add_option("--budget-of", q.budget_of,
                                    "a variant key: its time is the budget (variants not slower than it beyond the "
                                    "noise fit), the same on any machine")
                        ->excludes(budget);
  cmd->add_option("--max-error", q.max_error, "cheapest variant with error.rmse <= this (time ties: lowest rmse)")
      ->check(finite_number(0, false))
      ->excludes(budget)
      ->excludes(budget_of);
  cmd->add_option("--tolerance", q.tolerance,
                  "name a variant faster beyond the noise (budget; >= 5% when the table has no rounds) or with >= 5% "
                  "less error (max-error) that gives up at most this share of the other criterion")
      ->capture_default_str()
      ->check(finite_number(0, false) & CLI::Range(0.0, 1.0));
  cmd->add_option("--scene,-s", q.scene, "only this scene (default: all; worst over them)");
  cmd->add_option("--view", q.view, "only this view (default: each variant's worst view)");
  cmd->add_option("--backend,-b", q.backend, "only this backend (default: each separately)");
  cmd->add_option("--target", q.target,
                  "an AMD GPU family (sweep --gpu): decide by the estimate on it (gpu.<family>.est_ms: traced on the row's view, or the roofline) "
                  "instead of the time measured here; errors still from the reference");
  cmd->add_option("--calibration", a->calibration,
                  "refuse a table not measured with this calibration file (aovar calibrate; compared by content hash)");
  add_json(cmd, a->json);
  return {cmd, runs(a, run_select)};
}

}  // namespace aovar::cli
