// aovar generate: templates -> per-target sources, SPIR-V, variants.json and the C++ embedding; --check
// writes nothing and exits 1 when an output would change.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/options.h"
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

ExitCode generate(const CommonOptions& common, const compile::OutputOptions& out, const shard::ShardSpec& spec) {
  auto start = util::Clock::now();
  auto options = compile_options(common);
  // The shard is part of what was run: a shard's outputs never pass for the whole selection's, or another's.
  const std::string settings = compile::run_settings(compile::tool_identity(), common.manifest, options, out) +
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
  auto c = compile::plan_space(common.manifest, options);
  // Before anything is written: an empty selection would otherwise remove every output of a populated folder.
  if (auto problem = compile::empty_selection_problem(c, options.globs, util::display_path(common.manifest));
      !problem.empty())
    throw std::runtime_error(problem);
  std::optional<compile::GenerateShard> shard;
  if (spec.sharded()) {  // this shard's variants only: plan again without the others'
    shard = compile::plan_generate_shard(c, options, spec.index, spec.count, spec.convention);
    std::cerr << fmt::format("aovar: shard {}: {}\n", spec.label(), shard->balance);
    options.exclude.insert(shard->excluded.begin(), shard->excluded.end());
    c = compile::plan_space(common.manifest, options);
    if (!out.check) compile::write_generate_manifest(out.out, *shard, 0, false, 0);
  }
  compile::build_programs(c, options);
  if (!report_diagnostics(c)) return ExitCode::error;  // the diagnostics are printed
  auto r = compile::write_outputs(c, out);
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
  a.out.jobs = a.common.jobs;
  if (!a.depfile.empty()) a.out.depfile = a.depfile;
  if (!a.depfile_target.empty()) a.out.depfile_target = a.depfile_target;
  if (!a.stamp.empty()) a.out.stamp = a.stamp;
  const auto lock = a.out.check ? nullptr : lock_output(a.out.out);  // --check writes nothing
  return generate(a.common, a.out, shard_option(a.shard));
}

}  // namespace

Command add_generate(CLI::App& app) {
  auto a = std::make_shared<GenerateArgs>();
  auto* cmd = app.add_subcommand("generate", "templates -> per-target sources, SPIR-V, variants.json, C++ embedding");
  add_common(cmd, a->common);
  cmd->add_option("--out,-o", a->out_dir, "output folder")->required();
  cmd->add_option("--depfile", a->depfile, "write a gcc-style depfile listing the manifest and every template read");
  cmd->add_option("--depfile-target", a->depfile_target, "the output the depfile names (default: OUT/variants.json)");
  cmd->add_option("--stamp", a->stamp, "touch this file after a successful run (for build systems)");
  cmd->add_option("--emit", a->emit, "what to write: index,source,spirv,cpp")->capture_default_str();
  cmd->add_option("--namespace", a->out.cpp_namespace, "C++ namespace and file name of the embedding")
      ->capture_default_str();
  cmd->add_option("--shard", a->shard, shard_help);
  cmd->add_flag("--check", a->out.check, "write nothing; exit 1 when any output would change (CI staleness check)");
  return {cmd, [a] { return run_generate(*a); }};
}

}  // namespace aovar::cli
