// aovar gbuffer: the G-buffer file of a variant's formats for one view (docs/template-contract.md), the input a
// renderer outside aovar runs the variant's plan on (examples/render_variant).
#include <fmt/format.h>

#include <iostream>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/render_options.h"
#include "cli/subcommand.h"
#include "measure/gbuffer_export.h"
#include "util/fs.h"

namespace aovar::cli {
namespace {

struct GbufferArgs {
  CommonOptions common;
  measure::GbufferRequest request;
  std::string size = default_size, out;
};

ExitCode run_gbuffer(const GbufferArgs& a) {
  measure::GbufferRequest r = a.request;
  r.scope = a.common.scope();
  r.size = parse_size(a.size);
  if (r.radius < 0) throw std::runtime_error("--radius must be positive (world units; omit it for the scene's default)");
  const auto lock = lock_output_of_file(a.out);
  const render::GbufferImage image = measure::export_gbuffer(r);
  util::write_atomic(a.out, render::encode_gbuffer(image));
  std::cout << fmt::format("{}: the G-buffer of {} on {} at {}x{} ({} planes:", a.out, r.variant,
                           r.view.empty() ? "the first view" : r.view, r.size.width, r.size.height, image.planes.size());
  for (const auto& p : image.planes) std::cout << " " << p.name << " " << p.format;
  std::cout << ")\n";
  return ExitCode::ok;
}

}  // namespace

Command add_gbuffer(CLI::App& app) {
  auto [cmd, a] = subcommand<GbufferArgs>(
      app, "gbuffer", "write the G-buffer file of a variant's formats for one view (what examples/render_variant reads)");
  auto& r = a->request;
  add_manifest(cmd, a->common.manifest);
  add_cache_dir(cmd, a->common.cache_dir, "compile cache");
  cmd->add_flag("--no-cache", a->common.no_cache, "compile everything, read and write no cache");
  add_threads(cmd, a->common);
  cmd->add_option("--variant", r.variant, "the variant key (aovar list shows them)")->required();
  cmd->add_option("--scene,-s", r.scene, scene_help("the scene"))->capture_default_str();
  cmd->add_option("--views-file", r.views_file, "views side file (TOML or JSON) for the scene");
  cmd->add_option("--view", r.view, "view name (default: the scene's first view)");
  cmd->add_option("--size", a->size, "frame size WxH (what the variant was measured at)")->capture_default_str();
  cmd->add_option("--radius", r.radius, "AO radius in world units (default: the scene's)");
  add_device(cmd, r.device);
  cmd->add_option("--out,-o", a->out, "the G-buffer file to write")->required();
  return {cmd, runs(a, run_gbuffer)};
}

}  // namespace aovar::cli
