// A generator-only aovar (AOVAR_WITH_RENDER=OFF: glslang, SPIRV-Tools, toml++, JSON, CLI11, fmt and xxHash,
// without Embree, TBB, OSMesa or Vulkan) still lists every subcommand, so that a script calling one it
// lacks gets one line saying why and what to do instead of CLI11's "unknown subcommand".
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "cli/render_parts.h"

namespace aovar::cli {
namespace {

// One line for a subcommand or option this build does not have.
std::string without_render_message(const std::string& what) {
  return what + " is not in this build: aovar was configured with AOVAR_WITH_RENDER=OFF (the generator alone: "
                "list, generate, analyze --in); reconfigure with -DAOVAR_WITH_RENDER=ON to have it";
}


// The subcommand with any options (allow_extras: the message, not a usage error, is the answer).
Command unavailable(CLI::App& app, const std::string& name, const std::string& description) {
  auto* cmd = app.add_subcommand(name, description + " [not in this build: AOVAR_WITH_RENDER=OFF]");
  cmd->allow_extras();
  return {cmd, [name]() -> ExitCode { throw std::runtime_error(without_render_message("aovar " + name)); }};
}

}  // namespace

ExitCode run_analyze_gpu(const GpuAnalyzeArgs&) { throw std::runtime_error(without_render_message("aovar analyze --gpu")); }
TableChoice choose_from_table(const TableRequestArgs&) {
  throw std::runtime_error(without_render_message("aovar generate --from-table"));
}
variants::CalibratedValues calibration_values(const std::string&, const variants::Manifest&) {
  throw std::runtime_error(without_render_message("aovar generate --calibration"));
}
ExitCode run_list_scene(const ListArgs&) { throw std::runtime_error(without_render_message("aovar list --scene")); }

Command add_profile(CLI::App& app) { return unavailable(app, "profile", "what a scene needs and what it lets you drop"); }
Command add_measure(CLI::App& app) { return unavailable(app, "measure", "render and time variants on a scene"); }
Command add_calibrate(CLI::App& app) { return unavailable(app, "calibrate", "fit each method's parameters to references"); }
Command add_gbuffer(CLI::App& app) {
  return unavailable(app, "gbuffer", "write the G-buffer file of a variant for one view");
}
Command add_reference(CLI::App& app) { return unavailable(app, "reference", "ray-trace the ground-truth AO of a scene"); }
Command add_select(CLI::App& app) { return unavailable(app, "select", "pick the variant to ship from a cost table"); }
Command add_diff(CLI::App& app) { return unavailable(app, "diff", "per-variant deltas between two cost tables"); }
Command add_merge(CLI::App& app) { return unavailable(app, "merge", "join shard cost tables"); }
Command add_report(CLI::App& app) { return unavailable(app, "report", "report.md and report.html from a cost table"); }
Command add_stress(CLI::App& app) { return unavailable(app, "stress", "numerical stability of every variant"); }
Command add_sweep(CLI::App& app) { return unavailable(app, "sweep", "variants x scenes x views against the reference"); }
Command add_ship(CLI::App& app) { return unavailable(app, "ship", "from a scene to the variant to ship"); }

}  // namespace aovar::cli
