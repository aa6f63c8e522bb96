// aovar analyze: static cost per program and variant of a generated folder (SPIR-V) -> analysis.json;
// with --gpu, AMD ISA statistics per GPU family from RADV's null device -> gpu.json.
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "analyze/analyze.h"
#include "analyze/text.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "gpu/costs.h"
#include "gpu/families.h"
#include "gpu/gpu.h"
#include "gpu/text.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct AnalyzeArgs {
  std::string in;
  std::string gpu;  // --gpu FAMILY[,FAMILY...]
  std::string out;  // --gpu: folder for gpu.json
  std::string size = "1920x1080";  // --gpu: frame the roofline estimate is for
  CommonOptions common;
};

ExitCode run_analyze(const std::string& dir) {
  auto a = analyze::analyze_folder(dir);
  std::cout << analyze::program_table(a);
  auto out = std::filesystem::path(dir) / "analysis.json";
  util::write_if_changed(out, analyze::analysis_json(a));
  std::cout << analyze::summary_line(a, out);
  return ExitCode::ok;
}

// Exit 2 (an error) when a family failed (its error is in the table and gpu.json); the other families' results stand.
ExitCode run_analyze_gpu(const AnalyzeArgs& a) {
  const gpu::Frame frame = parse_size(a.size);
  gpu::GpuOptions options;
  options.families = gpu::parse_families(a.gpu);
  options.icd = gpu::find_radeon_icd();  // before compiling: a missing driver is the first thing to say
  compile::CompileOptions co = compile_options(a.common);
  co.targets = {variants::Target::vulkan};
  const auto compiled = compile::compile_space(a.common.manifest, co);
  if (!report_diagnostics(compiled)) return ExitCode::error;  // the diagnostics are printed
  std::vector<int> variants(compiled.space.variants.size());
  for (std::size_t i = 0; i < variants.size(); ++i) variants[i] = static_cast<int>(i);
  const gpu::GpuAnalysis result = gpu::analyze_gpu(compiled, variants, options);
  const gpu::VariantCosts costs = gpu::costs_of(result, gpu::variant_loads(compiled, variants), frame);
  std::cout << gpu::to_text(result, &costs);
  if (!a.out.empty()) {
    const auto path = std::filesystem::path(a.out) / "gpu.json";
    std::filesystem::create_directories(a.out);
    util::write_atomic(path, gpu::to_json(result, &costs));
    std::cout << fmt::format("wrote {}\n", path.string());
  }
  for (const auto& f : result.families)
    if (!f.ok()) return ExitCode::error;
  return ExitCode::ok;
}

}  // namespace

Command add_analyze(CLI::App& app) {
  auto a = std::make_shared<AnalyzeArgs>();
  auto* cmd = app.add_subcommand(
      "analyze", "static cost per program and variant: of a generated folder (SPIR-V), or on AMD GPUs (--gpu)");
  auto* in = cmd->add_option("--in", a->in, "folder written by `aovar generate --emit index,spirv`");
  auto* gpu = cmd->add_option("--gpu", a->gpu,
                              "AMD GPU families (e.g. navi21,vangogh,polaris10): compile every pass on RADV's null "
                              "device and print ACO's statistics; variants from the manifest");
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
  return {cmd, [a, cmd] {
            if (cmd->count("--gpu")) return run_analyze_gpu(*a);
            if (a->in.empty()) throw std::runtime_error("analyze: give --in DIR (a generated folder) or --gpu FAMILY");
            return run_analyze(a->in);
          }};
}

}  // namespace aovar::cli
