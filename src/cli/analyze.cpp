// aovar analyze: static cost per program and variant of a generated folder (SPIR-V) -> analysis.json;
// with --gpu, compiler statistics per GPU (RADV's null device for AMD, Mesa's GL drivers for the rest) -> gpu.json.
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "analyze/analyze.h"
#include "analyze/text.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/render_parts.h"
#include "cli/subcommand.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

ExitCode run_analyze(const std::string& dir) {
  const auto lock = lock_output(dir);  // analysis.json goes into the generated folder
  auto a = analyze::analyze_folder(dir);
  std::cout << analyze::program_table(a);
  auto out = std::filesystem::path(dir) / "analysis.json";
  util::write_if_changed(out, analyze::analysis_json(a));
  std::cout << analyze::summary_line(a, out);
  return ExitCode::ok;
}

}  // namespace

Command add_analyze(CLI::App& app) {
  auto [cmd, a] = subcommand<GpuAnalyzeArgs>(
      app, "analyze", "static cost per program and variant: of a generated folder (SPIR-V), or on GPUs (--gpu)");
  auto in_dir = std::make_shared<std::string>();
  auto* in = cmd->add_option("--in", *in_dir, "folder written by `aovar generate --emit index,spirv`");
  auto* gpu = cmd->add_option("--gpu", a->families,
                              "GPUs: AMD families (e.g. navi21,vangogh,polaris10; RADV's null device) and GL chips "
                              "(e.g. gt200,gf110,a320,a530,t760,byt; all in docs/gpu-cost.md; Mesa's GL drivers "
                              "through drm-shim): compile every pass and print the compilers' statistics; "
                              "variants from the manifest");
  cmd->add_option("--out", a->out, "with --gpu: write gpu.json to this folder")->needs(gpu);
  cmd->add_option("--size", a->size,
                  "with --gpu: frame WIDTHxHEIGHT of the roofline estimate on each family's product "
                  "(default 1920x1080)")->needs(gpu);
  add_manifest(cmd, a->common.manifest);
  cmd->add_option("--variants", a->common.globs, "with --gpu: only variants whose key matches this glob (repeatable)");
  cmd->add_option("--jobs,-j", a->common.jobs, "compile threads (default: cores)");
  add_cache_dir(cmd, a->common.cache_dir, "compile cache");
  cmd->add_flag("--no-cache", a->common.no_cache, "compile everything, read and write no cache");
  in->excludes(gpu);
  return {cmd, runs(a, [in_dir, cmd](const GpuAnalyzeArgs& args) {
            if (cmd->count("--gpu")) return run_analyze_gpu(args);
            if (in_dir->empty()) throw std::runtime_error("analyze: give --in DIR (a generated folder) or --gpu FAMILY");
            return run_analyze(*in_dir);
          })};
}

}  // namespace aovar::cli
