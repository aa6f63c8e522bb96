#include "cli/options.h"

#include "variants/manifest.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "cli/commands.h"
#include "cli/limits.h"
#include "compile/cache.h"
#include "compile/text.h"
#include "util/text.h"

namespace aovar::cli {

std::string default_manifest_path() {
  if (std::filesystem::exists(default_manifest)) return default_manifest;
  std::error_code error;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return default_manifest;
  const auto installed = exe.parent_path().parent_path() / "share/aovar/shader_src/aovar.toml";
  return std::filesystem::exists(installed) ? installed.string() : default_manifest;
}

void add_json(CLI::App* cmd, bool& json) {
  cmd->add_flag("--json", json, "print one JSON document (with schema_version) instead of the text");
}

CLI::Validator finite_number(double min, bool strict) {
  const std::string bound = fmt::format("{} {}", strict ? ">" : ">=", min);
  return CLI::Validator(
      [min, strict, bound](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || (strict ? v <= min : v < min))
          return fmt::format("'{}' is not a finite number {}", text, bound);
        return "";
      },
      "NUMBER " + bound);
}

void add_manifest(CLI::App* cmd, std::string& manifest) {
  if (manifest == default_manifest) manifest = default_manifest_path();
  cmd->add_option("--manifest,-m", manifest, "manifest file")->capture_default_str();
}

void add_cache_dir(CLI::App* cmd, std::string& dir, const std::string& holds) {
  cmd->add_option("--cache-dir", dir, holds + " " + cache_dir_default_help);
}

std::unique_ptr<util::OutputLock> lock_output(const std::filesystem::path& folder) {
  return folder.empty() ? nullptr : std::make_unique<util::OutputLock>(folder);
}

std::unique_ptr<util::OutputLock> lock_output_of_file(const std::filesystem::path& file) {
  return std::make_unique<util::OutputLock>(file.has_parent_path() ? file.parent_path() : ".", false);
}

std::filesystem::path cache_dir(const std::string& option, bool no_cache) {
  if (no_cache) return {};
  return option.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(option);
}

void add_common(CLI::App* cmd, CommonOptions& o) {
  add_manifest(cmd, o.manifest);
  cmd->add_option("--variants", o.globs, "only variants whose key matches this glob (repeatable)");
  cmd->add_option("--targets", o.targets, "vulkan,gl45,gles30 (default: the manifest's)")->delimiter(',');
  cmd->add_option("--jobs,-j", o.jobs, "compile threads (default: cores)")->check(whole_number(0, kMaxThreads));
  cmd->add_flag("--werror", o.werror, "treat glslang warnings as errors");
  add_cache_dir(cmd, o.cache_dir, "compile cache");
  cmd->add_flag("--no-cache", o.no_cache, "compile everything, read and write no cache");
}

const compile::RunScope& CommonOptions::scope() const {
  if (scope_) return *scope_;
  compile::RunScope s;
  s.manifest = std::filesystem::path(manifest);
  s.cache_dir = cache();
  s.threads = threads;
  s.jobs = jobs;
  for (const auto& t : targets) {
    auto target = variants::parse_target(t);
    if (!target) throw std::runtime_error("--targets: unknown target '" + t + "' (use vulkan, gl45, gles30)");
    s.targets.push_back(*target);
  }
  return scope_.emplace(std::move(s));
}

void add_threads(CLI::App* cmd, CommonOptions& o) {
  cmd->add_option("--threads", o.threads, "rendering threads (LP_NUM_THREADS for llvmpipe)")->check(whole_number(1, kMaxThreads))->capture_default_str();
}

compile::CompileOptions compile_options(const CommonOptions& o) {
  compile::CompileOptions c{o.scope()};
  c.werror = o.werror;
  c.globs = o.globs;
  return c;
}

bool report_diagnostics(const compile::CompiledSpace& c) {
  for (const auto& d : c.diagnostics) std::cerr << d << "\n";
  if (c.ok()) return true;
  std::cerr << compile::failure_line(c);
  return false;
}

shard::ShardSpec shard_option(const std::string& text) {
  shard::ShardSpec spec = shard::parse_shard_option(text, shard::process_env());
  if (text == "auto") {
    std::cerr << "aovar: " << spec.describe() << "\n";
    shard::touch_status_file(spec);
  }
  return spec;
}

std::string usage_error_line(const std::vector<Command>& commands, const std::string& what) {
  std::string command = "aovar";
  for (const auto& c : commands)
    if (c.app->parsed()) command += " " + c.app->get_name();
  return fmt::format("{}: {} ({} --help lists the options)", command, util::one_line(what), command);
}

ExitCode run_guarded(const std::function<ExitCode()>& run, const std::string& command) {
  try {
    return run();
  } catch (const std::exception& e) {
    // An option's own error ("--gpu-size: expected WxH ...") is told with the command that was run.
    const std::string what = e.what();
    std::cerr << (what.rfind("--", 0) == 0 && !command.empty() ? "aovar " + command + ": " : "") << what << "\n";
    return ExitCode::error;
  }
}

}  // namespace aovar::cli
