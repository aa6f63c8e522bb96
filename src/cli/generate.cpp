// aovar generate: templates -> per-target sources, SPIR-V, variants.json and the C++ embedding; --check
// writes nothing and exits 1 when an output would change.
#include <iostream>
#include <memory>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/options.h"
#include "compile/text.h"
#include "compile/up_to_date.h"
#include "util/clock.h"

namespace aovar::cli {
namespace {

struct GenerateArgs {
  CommonOptions common;
  compile::OutputOptions out;
  std::string out_dir, depfile, depfile_target, stamp, emit = "index,source,spirv,cpp";
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

int generate(const CommonOptions& common, const compile::OutputOptions& out) {
  auto start = util::Clock::now();
  auto options = compile_options(common);
  // Up to date: proven from the recorded inputs' hashes, before parsing the manifest or expanding anything.
  std::string settings = compile::run_settings(compile::tool_identity(), common.manifest, options, out);
  if (!out.check) {
    if (auto recorded = compile::recorded_if_current(settings, out)) {
      compile::finish_outputs(recorded->manifest, recorded->files, out);
      std::cout << compile::up_to_date_text(recorded->summary, out.out, util::seconds_since(start));
      return 0;
    }
  }
  auto c = compile::plan_space(common.manifest, options);
  compile::build_programs(c, options);
  if (!report_diagnostics(c)) return 1;
  auto r = compile::write_outputs(c, out);
  if (out.check) {
    std::cerr << compile::stale_text(r, out.out);
    if (!r.changed.empty()) return 1;
    std::cout << compile::up_to_date_line(r, out.out);
    return 0;
  }
  std::string summary = compile::summary_table(c);
  compile::record_run(settings, c, out, summary, r.files);
  std::cout << summary << compile::written_line(r, out.out, util::seconds_since(start));
  return 0;
}

int run_generate(GenerateArgs& a) {
  a.out.out = a.out_dir;
  a.out.emit = parse_emit(a.emit);
  a.out.jobs = a.common.jobs;
  if (!a.depfile.empty()) a.out.depfile = a.depfile;
  if (!a.depfile_target.empty()) a.out.depfile_target = a.depfile_target;
  if (!a.stamp.empty()) a.out.stamp = a.stamp;
  return generate(a.common, a.out);
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
  cmd->add_flag("--check", a->out.check, "write nothing; exit 1 when any output would change (CI staleness check)");
  return {cmd, [a] { return run_generate(*a); }};
}

}  // namespace aovar::cli
