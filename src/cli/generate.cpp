// aovar generate: templates -> per-target sources, SPIR-V, variants.json and the C++ embedding; --check
// writes nothing and exits 1 when an output would change.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/render_parts.h"
#include "cli/subcommand.h"
#include "compile/shard_plan.h"
#include "compile/text.h"
#include "compile/up_to_date.h"
#include "util/clock.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct GenerateArgs {
  CommonOptions common;
  compile::OutputOptions out;
  std::string out_dir, depfile, depfile_target, stamp, emit = "index,source,spirv,cpp", shard;
  TableRequestArgs table;  // --from-table: the selection and the pick table come from a cost table
  std::string calibration;  // --calibration: the fitted values the variants embed
  bool check_table = false;  // --check-table: the table's checks only, nothing compiled or written
};

// "index,source,spirv,cpp" -> compile::Emit bits; throws std::runtime_error naming an unknown item.
unsigned parse_emit(const std::string& emit) {
  unsigned bits = 0;
  std::size_t start = 0;
  while (start <= emit.size()) {
    std::size_t end = emit.find(',', start);
    std::string item = emit.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (item == "index") bits |= compile::emit_index;
    else if (item == "source") bits |= compile::emit_source;
    else if (item == "spirv") bits |= compile::emit_spirv;
    else if (item == "cpp") bits |= compile::emit_cpp;
    else throw std::runtime_error("--emit: unknown item '" + item + "' (use index, source, spirv, cpp)");
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return bits;
}

// `from_table`: the cost table the selection came from (its keys are common.globs), for the manifest check.
ExitCode generate(const CommonOptions& common, const compile::OutputOptions& out, const shard::ShardSpec& spec,
                  const std::string& from_table) {
  auto start = util::Clock::now();
  auto options = compile_options(common);
  // The shard is part of what was run: a shard's outputs never pass for the whole selection's, or another's.
  const std::string settings = compile::run_settings(compile::tool_identity(), options, out) +
                               (spec.sharded() ? "\nshard " + spec.label() : std::string());
  // Up to date: proven from the recorded inputs' hashes, before parsing the manifest or expanding anything.
  // A shard always plans (its shard.json is written from the plan); shards run once each on fresh machines.
  if (!out.check && !spec.sharded()) {
    if (auto recorded = compile::recorded_if_current(settings, out)) {
      compile::finish_outputs(recorded->manifest, recorded->files, out);
      std::cout << compile::up_to_date_text(recorded->summary, out.out, util::seconds_since(start));
      return ExitCode::ok;
    }
  }
  auto c = compile::plan_space(options);
  if (!from_table.empty())
    if (auto problem = compile::foreign_table_problem(c, options.globs, from_table, util::display_path(common.manifest));
        !problem.empty())
      throw std::runtime_error(problem);
  // Before anything is written: an empty selection would otherwise remove every output of a populated folder.
  if (auto problem = compile::empty_selection_problem(c, options.globs, util::display_path(common.manifest));
      !problem.empty())
    throw std::runtime_error(problem);
  std::optional<compile::GenerateShard> shard;
  if (spec.sharded()) {  // this shard's variants only: plan again without the others'
    shard = compile::plan_generate_shard(c, options, spec.index, spec.count, spec.convention);
    std::cerr << fmt::format("aovar: shard {}: {}\n", spec.label(), shard->balance);
    options.exclude.insert(shard->excluded.begin(), shard->excluded.end());
    c = compile::plan_space(options);
    if (!out.check) compile::write_generate_manifest(out.out, *shard, 0, false, 0);
  }
  compile::build_programs(c, options);
  if (!report_diagnostics(c)) return ExitCode::error;  // the diagnostics are printed
  auto r = compile::write_outputs(c, out, options.scope.jobs);
  if (out.check) {
    std::cerr << compile::stale_text(r, out.out);
    if (!r.changed.empty()) return ExitCode::check_failed;
    std::cout << compile::up_to_date_line(r, out.out);
    return ExitCode::ok;
  }
  std::string summary = compile::summary_table(c);
  compile::record_run(settings, c, out, summary, r.files);
  std::cout << summary << compile::written_line(r, out.out, util::seconds_since(start));
  if (shard)
    compile::write_generate_manifest(out.out, *shard, static_cast<int>(c.space.variants.size()), true,
                                     util::seconds_since(start));
  return ExitCode::ok;
}

ExitCode run_generate(GenerateArgs& a) {
  a.out.out = a.out_dir;
  a.out.emit = parse_emit(a.emit);
  if (!a.depfile.empty()) a.out.depfile = a.depfile;
  if (!a.depfile_target.empty()) a.out.depfile_target = a.depfile_target;
  if (!a.stamp.empty()) a.out.stamp = a.stamp;
  if (!a.table.table.empty()) {
    if (!a.common.globs.empty())
      throw std::runtime_error("generate: --from-table chooses the variants; leave out --variants");
    a.table.manifest = a.common.manifest;
    TableChoice choice = choose_from_table(a.table);
    std::cerr << choice.summary;
    if (a.check_table) return ExitCode::ok;  // every refusal of the table has been made: CMake's configure step
    a.common.globs = std::move(choice.keys);  // exact keys: the glob path's outputs, depfile and no-op check
    a.out.pick_fronts = std::move(choice.fronts);
    a.out.parameters = std::move(choice.parameters);
    if (!choice.calibration.empty()) a.out.depends.push_back(choice.calibration);
  } else if (!a.table.targets.empty() || a.table.budget_ms || a.table.max_error || !a.table.budget_of.empty() ||
             a.check_table) {
    throw std::runtime_error("generate: --for, --budget-ms, --budget-of, --max-error and --check-table need --from-table");
  }
  if (!a.calibration.empty()) {
    if (!a.table.table.empty())
      throw std::runtime_error("generate: --from-table embeds the table's own calibration; leave out --calibration");
    a.out.parameters = calibration_values(a.calibration, a.common.scope().manifest.get());
    a.out.depends.push_back(a.calibration);
  }
  const auto lock = a.out.check ? nullptr : lock_output(a.out.out);  // --check writes nothing
  return generate(a.common, a.out, shard_option(a.shard), a.table.table.empty() ? std::string() : util::display_path(a.table.table));
}

}  // namespace

Command add_generate(CLI::App& app) {
  auto [cmd, a] = subcommand<GenerateArgs>(
      app, "generate",
      "templates -> per-target sources, SPIR-V, variants.json, C++ embedding");
  add_common(cmd, a->common);
  cmd->add_option("--out,-o", a->out_dir, "output folder")->required();
  cmd->add_option("--depfile", a->depfile, "write a gcc-style depfile listing the manifest and every template read");
  cmd->add_option("--depfile-target", a->depfile_target, "the output the depfile names (default: OUT/variants.json)");
  cmd->add_option("--stamp", a->stamp, "touch this file after a successful run (for build systems)");
  cmd->add_option("--emit", a->emit, "what to write: index,source,spirv,cpp")->capture_default_str();
  cmd->add_option("--namespace", a->out.cpp_namespace, "C++ namespace and file name of the embedding")
      ->capture_default_str();
  cmd->add_option("--shard", a->shard, shard_help);
  auto& t = a->table;
  cmd->add_option("--from-table", t.table,
                  "cost_table.json: generate the variants it keeps (per GPU family and measured backend, the front "
                  "select answers along) and embed the pick table (C++: pick(device, budget))");
  cmd->add_option("--for", t.targets, "with --from-table: only these GPU families / backends (default: all the table has)")
      ->delimiter(',');
  auto* budget = cmd->add_option("--budget-ms", t.budget_ms, "with --from-table: only select's pick within this budget per target")
                     ->check(finite_number(0, true));
  auto* budget_of = cmd->add_option("--budget-of", t.budget_of, "with --from-table: only select's pick no slower than this variant")
                        ->excludes(budget);
  cmd->add_option("--max-error", t.max_error, "with --from-table: only select's pick with rmse <= this per target")
      ->check(finite_number(0, false))
      ->excludes(budget)
      ->excludes(budget_of);
  cmd->add_option("--calibration", a->calibration,
                  "calibration.json (aovar calibrate, ship's OUT/calibration.json): embed its fitted values as each "
                  "variant's params, beside the manifest's (default: the manifest's values; --from-table: the table's)");
  cmd->add_flag("--check", a->out.check, "write nothing; exit 1 when any output would change (CI staleness check)");
  cmd->add_flag("--check-table", a->check_table,
                "with --from-table: make every check of the table (its manifest, names, targets and pick, the "
                "calibration it was scored with) and stop: nothing is compiled or written (CMake's FROM_TABLE runs it "
                "at configure)");
  return {cmd, runs(a, run_generate)};
}

}  // namespace aovar::cli
