// aovar: thin subcommands over the libraries (DESIGN.md §6).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <tuple>
#include <cstdio>
#include <functional>
#include <iostream>
#include <unistd.h>

#include "analyze/analyze.h"
#include "calibrate/calibrate.h"
#include "compile/cache.h"
#include "compile/generate.h"
#include "measure/measure.h"
#include "profile/scene_prune.h"
#include "sweep/sweep.h"
#include "reference/reference.h"
#include "report/report.h"
#include "profile/profile.h"
#include "scene/scene.h"
#include "stress/stress.h"
#include "shadergen/expand.h"
#include "table/compare.h"
#include "table/select.h"
#include "table/table.h"
#include "util/fs.h"

namespace {
using namespace aovar;

struct CommonOptions {
  std::string manifest = "shader_src/aovar.toml";
  std::vector<std::string> globs;
  std::vector<std::string> targets;
  int jobs = 0;
  bool werror = false;
  std::string cache_dir;
  bool no_cache = false;
};

void add_common(CLI::App* cmd, CommonOptions& o) {
  cmd->add_option("--manifest,-m", o.manifest, "manifest file")->capture_default_str();
  cmd->add_option("--variants", o.globs, "only variants whose key matches this glob (repeatable)");
  cmd->add_option("--targets", o.targets, "vulkan,gl45,gles30 (default: the manifest's)")->delimiter(',');
  cmd->add_option("--jobs,-j", o.jobs, "compile threads (default: cores)");
  cmd->add_flag("--werror", o.werror, "treat glslang warnings as errors");
  cmd->add_option("--cache-dir", o.cache_dir, "compile cache (default: $AOVAR_CACHE_DIR or ~/.cache/aovar)");
  cmd->add_flag("--no-cache", o.no_cache, "compile everything, read and write no cache");
}

compile::CompileOptions compile_options(const CommonOptions& o) {
  compile::CompileOptions c;
  for (const auto& t : o.targets) {
    auto target = variants::parse_target(t);
    if (!target) throw std::runtime_error("--targets: unknown target '" + t + "' (use vulkan, gl45, gles30)");
    c.targets.push_back(*target);
  }
  c.jobs = o.jobs;
  c.werror = o.werror;
  c.globs = o.globs;
  if (!o.no_cache) c.cache_dir = o.cache_dir.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(o.cache_dir);
  return c;
}

// Prints diagnostics; returns false (and says so) when anything failed.
bool report_diagnostics(const compile::CompiledSpace& c) {
  for (const auto& d : c.diagnostics) std::cerr << d << "\n";
  if (c.ok()) return true;
  int failed = 0;
  for (const auto& s : c.stats) failed += s.failed;
  std::cerr << fmt::format("aovar: {} error(s), {} program build(s) failed; nothing was written\n", c.errors, failed);
  return false;
}

std::string summary_table(const compile::CompiledSpace& c) {
  std::string s = fmt::format("{:<8} {:>9} {:>7} {:>9} {:>7} {:>7} {:>12}\n", "target", "programs", "unique",
                              "compiled", "cached", "failed", "spirv bytes");
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    const auto& st = c.stats[t];
    s += fmt::format("{:<8} {:>9} {:>7} {:>9} {:>7} {:>7} {:>12}\n", variants::target_name(c.targets[t]),
                     st.programs, st.unique, st.compiled, st.cached, st.failed, st.spirv_bytes);
  }
  return s + fmt::format("{}  ({} variants)\n", compile::counts_line(c), c.space.variants.size());
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run_list(const CommonOptions& o, bool show_pruned) {
  auto c = compile::compile_space(o.manifest, compile_options(o));
  if (!report_diagnostics(c)) return 1;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    std::cout << c.space.variants[v].key;
    if (c.variant_same_as[v] >= 0) std::cout << "  same as " << c.space.variants[c.variant_same_as[v]].key;
    std::cout << "\n";
  }
  if (show_pruned)
    for (const auto& p : c.space.pruned)
      std::cout << p.key << "  dropped: " << c.manifest.rules[p.rule].reason << " (" << c.manifest.error_prefix()
                << ":" << c.manifest.rules[p.rule].pos.line << ")\n";
  std::cout << "# " << compile::counts_line(c) << "\n";
  return 0;
}

int run_generate(const CommonOptions& o, const compile::OutputOptions& out) {
  auto start = std::chrono::steady_clock::now();
  auto options = compile_options(o);
  auto c = compile::plan_space(o.manifest, options);
  std::string print = compile::fingerprint(c, options, out);
  if (!out.check) {
    if (auto summary = compile::fresh_outputs(c, print, out)) {
      compile::finish_outputs(c, out);
      // The recorded table's compiled/cached columns describe the run that wrote the files: show only
      // its counts line.
      std::size_t counts = summary->find("space ");
      std::cout << (counts == std::string::npos ? std::string() : summary->substr(counts))
                << fmt::format("up to date: nothing compiled, no file written -> {} ({:.2f} s)\n",
                               util::display_path(out.out), seconds_since(start));
      return 0;
    }
  }
  compile::build_programs(c, options);
  if (!report_diagnostics(c)) return 1;
  auto r = compile::write_outputs(c, out);
  if (out.check) {
    for (std::size_t i = 0; i < r.changed.size() && i < 20; ++i) std::cerr << "stale: " << r.changed[i] << "\n";
    if (r.changed.size() > 20) std::cerr << "stale: ... and " << r.changed.size() - 20 << " more\n";
    if (!r.changed.empty()) {
      std::cerr << fmt::format("aovar: {} generated file(s) in {} are out of date: run aovar generate --out {}\n",
                               r.changed.size(), util::display_path(out.out), util::display_path(out.out));
      return 1;
    }
    std::cout << fmt::format("{} files up to date in {}\n", r.unchanged, util::display_path(out.out));
    return 0;
  }
  std::string summary = summary_table(c);
  compile::record_outputs(out, print, summary, r.files);
  std::cout << summary
            << fmt::format("files: {} written, {} unchanged, {} removed -> {} ({:.2f} s)\n", r.written, r.unchanged,
                           r.removed, util::display_path(out.out), seconds_since(start));
  return 0;
}

// Runs work(progress) with a one-line status on a terminal: status lines overwrite each other, lines that
// start with "note: " stay, and the status is cleared when the work ends or throws (so an error gets a
// line of its own).
template <class Work>
auto with_status(Work&& work) {
  const bool tty = isatty(fileno(stderr));
  std::function<void(const std::string&)> progress = [tty](const std::string& line) {
    if (line.rfind("note: ", 0) == 0) std::cerr << (tty ? "\r\033[K" : "") << line << "\n";
    else if (tty) std::cerr << "\r\033[K" << line << std::flush;
  };
  struct Clear {
    bool tty;
    ~Clear() {
      if (tty) std::cerr << "\r\033[K";
    }
  } clear{tty};
  return work(progress);
}

render::Extent parse_size(const std::string& text) {
  render::Extent e;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &e.width, &x, &e.height, &extra) != 3 || (x != 'x' && x != 'X') ||
      e.width < 1 || e.height < 1 || e.width > 16384 || e.height > 16384)
    throw std::runtime_error("--size: expected WxH such as 640x360 (1 to 16384 each), got '" + text + "'");
  return e;
}

render::ParamOverrides parse_params(const std::vector<std::string>& items) {
  render::ParamOverrides out;
  for (const auto& item : items) {
    auto eq = item.find('=');
    std::size_t used = 0;
    double value = 0;
    try {
      if (eq != std::string::npos) value = std::stod(item.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (eq == std::string::npos || item.find('.') > eq || used == 0 || used != item.size() - eq - 1)
      throw std::runtime_error("--param: expected PASS.NAME=NUMBER such as ao.intensity=1.5, got '" + item + "'");
    out[item.substr(0, eq)] = value;
  }
  return out;
}

// The measured rows as a table: one line per variant, view and backend.
void print_measure_table(const measure::MeasureResult& r) {
  bool truth = std::any_of(r.rows.begin(), r.rows.end(), [](const auto& row) { return row.error.has_value(); });
  std::cout << fmt::format("{:<46} {:<9} {:<10} {:>8} {:>8} {:>8} {:>6} {}  {}\n", "variant", "backend", "view",
                           "min ms", "median", "p90", "rel", truth ? "  rmse    ssim" : "", "passes (min ms)");
  for (const auto& row : r.rows) {
    std::string passes;
    for (const auto& [name, s] : row.passes) passes += fmt::format("{} {:.2f}  ", name, s.min);
    std::string error = !truth ? "" : row.error ? fmt::format("{:>6.4f} {:>7.4f}", row.error->rmse, row.error->ssim)
                                                : fmt::format("{:>14}", "-");
    std::cout << fmt::format("{:<46} {:<9} {:<10} {:>8.2f} {:>8.2f} {:>8.2f} {:>6.2f} {}  {}{}\n", row.variant,
                             row.backend, row.view, row.time_ms.min, row.time_ms.median, row.time_ms.p90, row.rel_time, error,
                             passes, row.is_baseline ? "(baseline)" : row.reused ? "(reused)" : "");
  }
}

int run_measure(const CommonOptions& common, measure::MeasureOptions o, const std::string& size,
                const std::vector<std::string>& params, const std::string& out, const std::string& reference_mode,
                const std::string& calibration, bool no_calibration) {
  o.manifest = common.manifest;
  o.reference_mode = reference::parse_mode(reference_mode);
  if (o.reference_rays < 1) throw std::runtime_error("--rays must be at least 1");
  if (!common.no_cache) o.reference_cache = common.cache_dir.empty() ? compile::CompileCache::default_dir()
                                                                     : std::filesystem::path(common.cache_dir);
  // The manifest's calibration (calibration.json next to it) applies unless another file or none is asked for.
  std::filesystem::path cal_file = calibration;
  if (cal_file.empty() && !no_calibration) {
    auto next_to = std::filesystem::path(common.manifest).parent_path() / "calibration.json";
    if (std::filesystem::exists(next_to)) cal_file = next_to;
  }
  if (!cal_file.empty() && !no_calibration) o.calibration = calibrate::load_calibration(cal_file);
  o.globs = common.globs;
  o.jobs = common.jobs;
  o.size = parse_size(size);
  if (o.radius < 0) throw std::runtime_error("--radius must be positive (world units; omit it for the scene's default)");
  if (o.warmup < 0) throw std::runtime_error("--warmup must be 0 or more");
  o.params = parse_params(params);
  o.out = out;
  if (!common.no_cache)
    o.cache_dir = common.cache_dir.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(common.cache_dir);
  auto r = with_status([&](const auto& progress) { return measure::run_measure(o, progress); });
  print_measure_table(r);
  for (const auto& d : r.devices)
    std::cout << fmt::format("# {}: {}, {}, {} threads\n", d.backend, d.device, d.api_version, d.threads);
  std::cout << fmt::format("# scene {} ({} triangles), radius {:.3g}, {} at {}, {} reps after {} warm-up; {}; "
                           "{} rows ({} reused) in {:.1f} s{}\n",
                           r.scene, r.triangles, r.radius, o.baseline, size, o.reps, o.warmup, r.counts, r.rows.size(),
                           r.reused, r.wall_s, out.empty() ? "" : " -> " + util::display_path(std::filesystem::path(out) / "measure.json"));
  if (r.pruning)
    std::cout << fmt::format("# pruned by the scene's profile: {} ({}){}\n", r.pruning->summary(o.globs),
                             r.pruning->reused ? fmt::format("profile reused in {:.2f} s", r.pruning->seconds)
                                               : fmt::format("profiled in {:.1f} s", r.pruning->seconds),
                             out.empty() ? std::string()
                                         : "; each with its reason in " +
                                               util::display_path(std::filesystem::path(out) / "measure.json") +
                                               " \"pruned\" (--no-prune measures them)");
  if (!o.calibration.empty())
    std::cout << "# calibrated parameters: " << util::display_path(cal_file) << " (--no-calibration: the manifest's defaults)\n";
  for (const auto& sheet : r.contact_sheets)
    std::cout << "# contact sheet: " << util::display_path(std::filesystem::path(out) / sheet) << "\n";
  return 0;
}

// "k/n" (1 <= k <= n) -> 0-based shard index and count.
std::pair<int, int> parse_shard(const std::string& text) {
  int k = 0, n = 0;
  char slash = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &k, &slash, &n) != 3 || slash != '/' || n < 1 || k < 1 || k > n)
    throw std::runtime_error("--shard: expected k/n with 1 <= k <= n (e.g. 2/4), got '" + text + "'");
  return {k - 1, n};
}

int run_sweep(const CommonOptions& common, sweep::SweepOptions o, const std::string& size, const std::string& shard,
              const std::string& calibration, bool no_calibration) {
  measure::MeasureOptions& m = o.measure;
  m.manifest = common.manifest;
  m.globs = common.globs;
  m.jobs = common.jobs;
  m.size = parse_size(size);
  if (!shard.empty()) std::tie(m.shard_index, m.shard_count) = parse_shard(shard);
  if (m.reference_rays < 1) throw std::runtime_error("--rays must be at least 1");
  auto cache = common.cache_dir.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(common.cache_dir);
  if (!common.no_cache) m.cache_dir = m.reference_cache = cache;
  std::filesystem::path cal_file = calibration;
  if (cal_file.empty() && !no_calibration) {
    auto next_to = std::filesystem::path(common.manifest).parent_path() / "calibration.json";
    if (std::filesystem::exists(next_to)) cal_file = next_to;
  }
  if (!cal_file.empty() && !no_calibration) m.calibration = calibrate::load_calibration(cal_file);
  auto r = with_status([&](const auto& progress) { return sweep::run_sweep(o, progress); });
  std::cout << table::to_markdown(r.table);
  for (const auto& m : r.table.meta.value("cost_models", nlohmann::json::array()))
    std::cout << fmt::format("# cost model {} {} {}: {} rows, cross-validated R2 {:.3f}, Spearman {:.3f} (against time_ms.min "
                             "{:.3f}; {} features){}\n",
                             m.at("scene").get<std::string>(), m.at("view").get<std::string>(),
                             m.at("backend").get<std::string>(), m.at("rows").get<int>(), m.at("cv_r2").get<double>(),
                             m.at("cv_spearman").get<double>(), m.value("cv_spearman_min", 0.0), m.value("features", "static + axes"),
                             m.value("predicts", false) ? ", predicts" : "");
  if (o.prune_dominated)
    std::cout << fmt::format("# prune: {} variants skipped as predicted dominated; {} more measured anyway as a check, "
                             "{} of them on the Pareto front (cost_table.json meta.prune)\n",
                             r.variants_skipped, r.variants_checked, r.checked_on_front);
  if (o.measure.prune_by_profile)
    std::cout << fmt::format("# scene profiles: {} ({} reused) in {:.2f} s; each dropped variant with its reason: "
                             "cost_table.json meta.pruned (--no-prune measures them)\n",
                             o.scenes.size(), r.profiles_reused, r.profile_s);
  std::cout << fmt::format("# {} rows ({} measured, {} reused, {} predicted) in {:.1f} s{} -> {}\n", r.table.rows.size(),
                           r.rows_measured, r.rows_reused, r.rows_predicted, r.wall_s, cal_file.empty() || no_calibration ? "" : ", calibrated by " + util::display_path(cal_file),
                           util::display_path(o.out / "cost_table.json"));
  std::cout << "# report: " << util::display_path(o.out / "report.html") << " (and report.md)\n";
  return 0;
}

int run_calibrate(const CommonOptions& common, calibrate::CalibrateOptions o, const std::string& out) {
  auto cache = common.cache_dir.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(common.cache_dir);
  o.compile_cache = o.reference_cache = cache;
  auto c = with_status([&](const auto& progress) { return calibrate::calibrate(o, progress); });
  calibrate::write_calibration(out, c);
  std::cout << fmt::format("{:<10} {:>6} {:>17} {:>19}  {}\n", "algorithm", "evals", "train rmse", "validation rmse",
                           "fitted (default)");
  for (const auto& f : c.fits) {
    std::string values;
    for (const auto& [key, value] : f.fitted) values += fmt::format("{} {:.4g} ({:.4g})  ", key, value, f.defaults.at(key));
    std::cout << fmt::format("{:<10} {:>6} {:>7.4f} -> {:>6.4f} {:>8.4f} -> {:>6.4f}  {}\n", f.algorithm, f.evaluations,
                             f.train_rmse_before, f.train_rmse_after, f.validation_rmse_before,
                             f.validation_rmse_after, values);
  }
  std::cout << fmt::format("# {} at {}x{}, references {} rays ({}); -> {}\n", c.backend, c.size.width, c.size.height,
                           c.rays, reference::mode_name(c.mode), util::display_path(out));
  return 0;
}

int run_analyze(const std::string& dir) {
  auto a = analyze::analyze_folder(dir);
  std::cout << analyze::program_table(a);
  auto out = std::filesystem::path(dir) / "analysis.json";
  util::write_if_changed(out, analyze::analysis_json(a));
  std::cout << fmt::format("# {} programs, {} variants (counts per pixel, upper bounds) -> {}\n", a.programs.size(),
                           a.variants.size(), util::display_path(out));
  return 0;
}

int run_reference(const CommonOptions& common, reference::RunOptions o, const std::string& size, const std::string& mode) {
  o.reference.size = parse_size(size);
  try {
    o.reference.mode = reference::parse_mode(mode);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("--mode: ") + e.what());
  }
  if (o.reference.rays < 1) throw std::runtime_error(fmt::format("--rays {}: need at least 1 ray per pixel", o.reference.rays));
  if (o.reference.threads < 0) throw std::runtime_error("--threads must be 0 (all cores) or more");
  if (o.reference.frame < 0) throw std::runtime_error("--frame must be 0 or more");
  if (!common.no_cache)
    o.reference.cache_dir = common.cache_dir.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(common.cache_dir);
  bool tty = isatty(fileno(stderr));
  auto status = [tty](const std::string& line, bool final) {
    if (final) std::cerr << (tty ? "\r\033[K" : "") << line << "\n";
    else if (tty) std::cerr << "\r\033[K" << line << std::flush;
  };
  reference::RunResult r;
  try {
    r = reference::run_reference(o, status);
  } catch (...) {
    if (tty) std::cerr << "\r\033[K";  // the error goes on a line of its own, not after the status
    throw;
  }
  std::cout << fmt::format("{:<12} {:>9} {:>6} {:<10} {:>8} {:>9} {:>9} {:>7} {:>9} {:>8}\n", "view", "size", "rays",
                           "mode", "radius", "mean vis", "mean err", "bg %", "trace s", "Mrays/s");
  for (const auto& v : r.views)
    std::cout << fmt::format("{:<12} {:>9} {:>6} {:<10} {:>8.4g} {:>9.4f} {:>9.4f} {:>7.1f} {:>9.2f} {:>8.2f}{}\n", v.view,
                             fmt::format("{}x{}", v.options.size.width, v.options.size.height), v.options.rays,
                             reference::mode_name(v.options.mode), v.options.radius, v.stats.mean_visibility,
                             v.stats.mean_std_error, 100.0 * v.stats.background_share, v.trace_s,
                             v.trace_s > 0 ? static_cast<double>(v.rays_traced) / v.trace_s / 1e6 : 0.0,
                             v.from_cache ? "  (cached)" : "");
  std::cout << fmt::format("# scene {} ({} triangles) in {:.1f} s -> {}\n", r.scene, r.triangles, r.wall_s,
                           util::display_path(o.out / "reference.json"));
  return 0;
}

// aovar select: the choice, the reason, the margin and the runners-up; exit 1 when nothing satisfies.
int run_select(const std::string& table_path, const table::SelectQuery& q) {
  auto sel = table::select(table::read_table(table_path), q);
  (sel.ok ? std::cout : std::cerr) << sel.text;
  return sel.ok ? 0 : 1;
}

int run_diff(const std::string& a, const std::string& b) {
  auto d = table::diff_tables(table::read_table(a), table::read_table(b));
  std::cout << table::format_diff(d, a, b);
  return 0;
}

// "x,y,z" -> vec3 (inf and nan are spelled as strtof reads them).
glm::vec3 parse_vec3(const std::string& text, const char* option) {
  float v[3];
  const char* p = text.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[i] = std::strtof(p, &end);
    if (end == p || (i < 2 && *end != ',') || (i == 2 && *end != '\0'))
      throw std::runtime_error(fmt::format("{}: expected x,y,z (e.g. 1,2.5,-3), got '{}'", option, text));
    p = end + 1;
  }
  return {v[0], v[1], v[2]};
}

struct ProfileCli {
  profile::Options options;
  std::string size = "640x360", out;
  bool no_flicker = false, no_cache = false;
};

profile::Options profile_options(ProfileCli& a, const std::string& manifest) {
  profile::Options o = a.options;
  o.manifest = manifest;
  o.size = parse_size(a.size);
  o.measure_flicker = !a.no_flicker;
  if (!a.no_cache) o.cache_dir = compile::CompileCache::default_dir();
  return o;
}

// aovar profile: what the scene needs, with evidence; profile.json with --out.
int run_profile(ProfileCli& a, const std::string& manifest) {
  auto o = profile_options(a, manifest);
  // The manifest and its space once: the profile picks its flicker pair from the space, which is then pruned.
  const auto loaded = variants::load_manifest(o.manifest);
  const auto space = variants::build_space(loaded);
  const auto sc = scene::load_scene(o.scene);
  auto p = with_status([&](const auto& progress) { return profile::profile_scene(o, sc, loaded, space, progress); });
  std::cout << profile::to_text(p);
  auto pruned = profile::prune(loaded, space, p);
  std::cout << fmt::format("# {} variants after rules; the scene keeps {} and drops {} (aovar list --scene {} --pruned)\n",
                           space.variants.size(), pruned.kept.size(), pruned.dropped.size(), o.scene);
  if (!a.out.empty()) {
    auto j = profile::to_json(p);
    j["kept"] = pruned.kept.size();
    j["dropped"] = pruned.dropped.size();
    util::write_atomic(std::filesystem::path(a.out) / "profile.json", j.dump(1) + "\n");
  }
  return 0;
}

// aovar list --scene: the variants the scene's profile keeps; --pruned adds every dropped one with its reason.
int run_list_scene(const CommonOptions& c, ProfileCli& a, bool show_pruned) {
  auto o = profile_options(a, c.manifest);
  // The manifest and its whole space once: the profile picks its flicker pair from it, the globs select
  // from it what is pruned.
  const auto manifest = variants::load_manifest(o.manifest);
  const auto space = variants::build_space(manifest);
  const auto sc = scene::load_scene(o.scene);
  auto p = with_status([&](const auto& progress) { return profile::profile_scene(o, sc, manifest, space, progress); });
  auto pruned = profile::prune(manifest, space, p, c.globs);
  for (const auto& k : pruned.kept) std::cout << k << "\n";
  if (show_pruned) {
    for (const auto& r : space.pruned)
      std::cout << r.key << "  dropped: " << manifest.rules[r.rule].reason << " (" << manifest.error_prefix() << ":"
                << manifest.rules[r.rule].pos.line << ")\n";
    for (const auto& [k, why] : pruned.dropped) std::cout << k << "  dropped for " << o.scene << ": " << why << "\n";
  }
  std::cout << fmt::format("# space {} / rules {} / selected {} / scene {} keeps {} ({} dropped, with reasons: --pruned)\n",
                           space.space, space.collapsed, pruned.kept.size() + pruned.dropped.size(), o.scene,
                           pruned.kept.size(), pruned.dropped.size());
  return 0;
}

struct StressCli {
  CommonOptions common;
  stress::Options options;
  std::string size = "96x54", out, calibration, scene, eye, target, up = "0,1,0";
  std::vector<std::string> case_names;
  float fov = 60, near_plane = 0.1f, far_plane = 100, radius = 0;
  bool no_calibration = false, list_cases = false, no_reuse = false, mediump_fp32 = false;
};

// aovar stress: per-variant pass/fail over the stress cases; exit 1 when a shipped variant fails.
int run_stress(StressCli& a) {
  if (a.list_cases) {
    for (const auto& c : stress::default_cases())
      std::cout << fmt::format("{:<20} {:<18} {}\n", c.name, c.scene, c.what);
    return 0;
  }
  stress::Options& o = a.options;
  o.manifest = a.common.manifest;
  o.globs = a.common.globs;
  o.jobs = a.common.jobs;
  o.size = parse_size(a.size);
  o.out = a.out;
  o.reuse = !a.no_reuse;
  o.mediump_fp16 = !a.mediump_fp32;
  auto cache = a.common.cache_dir.empty() ? compile::CompileCache::default_dir() : std::filesystem::path(a.common.cache_dir);
  if (!a.common.no_cache) o.cache_dir = o.reference_cache = cache;
  std::filesystem::path cal_file = a.calibration;
  if (cal_file.empty() && !a.no_calibration) {
    auto next_to = std::filesystem::path(a.common.manifest).parent_path() / "calibration.json";
    if (std::filesystem::exists(next_to)) cal_file = next_to;
  }
  if (!cal_file.empty() && !a.no_calibration) o.calibration = calibrate::load_calibration(cal_file);
  if (!a.scene.empty() || !a.eye.empty() || !a.target.empty()) {
    if (a.scene.empty() || a.eye.empty() || a.target.empty())
      throw std::runtime_error("stress: a custom case needs --scene, --eye and --target (and optionally --up, --fov, --near, --far, --radius)");
    o.cases.push_back(stress::custom_case(a.scene, parse_vec3(a.eye, "--eye"), parse_vec3(a.target, "--target"), a.fov,
                                          a.near_plane, a.far_plane, a.radius, parse_vec3(a.up, "--up")));
  }
  if (!a.case_names.empty()) {
    auto all = stress::default_cases();
    for (const auto& name : a.case_names) {
      auto it = std::find_if(all.begin(), all.end(), [&](const stress::Case& c) { return c.name == name; });
      if (it == all.end()) {
        std::string names;
        for (const auto& c : all) names += (names.empty() ? "" : ", ") + c.name;
        throw std::runtime_error("stress: unknown --case '" + name + "' (cases: " + names + ")");
      }
      o.cases.push_back(*it);
    }
  }
  auto r = with_status([&](const auto& progress) { return stress::run_stress(o, progress); });
  const auto cases = o.cases.empty() ? stress::default_cases() : o.cases;
  for (const auto& v : r.variants) {
    if (v.failures.empty()) continue;
    std::cout << fmt::format("FAIL {}{}\n", v.variant, v.shipped ? " (shipped)" : "");
    for (std::size_t i : v.failures) {
      const auto& c = r.checks[i];
      std::cout << fmt::format("  {} ({}): {}\n    reproduce: {}\n", c.case_name, c.backend, c.failure,
                               stress::reproducer(o, c, cases));
    }
  }
  std::cout << fmt::format("# {} variants x {} cases x {} backends: {} checks ({} reused), {} variants failed, {} of them "
                           "shipped, in {:.1f} s{}\n",
                           r.variants.size(), cases.size(), o.backends.size(), r.checks.size(), r.reused, r.failed,
                           r.shipped_failed, r.wall_s,
                           o.out.empty() ? "" : " -> " + util::display_path(o.out / "stress.md") + " and stress.json");
  return r.shipped_failed > 0 ? 1 : 0;
}

// aovar report: report.md and report.html from a cost table (a sweep's, a merged one, an edited one).
int run_report(const std::string& table_path, const std::string& out) {
  auto t = table::read_table(table_path);
  std::filesystem::path images = std::filesystem::path(table_path).parent_path();
  std::filesystem::path dir = out.empty() ? images : std::filesystem::path(out);
  if (images.empty()) images = ".";
  if (dir.empty()) dir = ".";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(util::display_path(dir) + ": error: cannot create the output folder: " + ec.message());
  report::write_reports(t, dir, images);
  std::cout << fmt::format("{} rows -> {} and {}\n", t.rows.size(), util::display_path(dir / "report.md"),
                           util::display_path(dir / "report.html"));
  return 0;
}

int run_merge(const std::string& out, const std::vector<std::string>& inputs) {
  std::vector<std::filesystem::path> in(inputs.begin(), inputs.end());
  auto t = table::merge_tables(in);
  table::write_json(t, out);
  std::cout << fmt::format("{} rows from {} tables -> {}\n", t.rows.size(), in.size(), util::display_path(out));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"aovar: generate, validate and measure SSAO shader variants"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("aovar 0.1.0 (") + compile::compiler_version() + ")");

  CommonOptions list_opts;
  bool show_pruned = false;
  auto* list = app.add_subcommand("list", "print the variants after rules (one key a line) and the counts");
  add_common(list, list_opts);
  list->add_flag("--pruned", show_pruned, "also print every dropped variant with the rule's reason");
  ProfileCli list_profile;
  list->add_option("--scene,-s", list_profile.options.scene,
                   "keep only what this scene needs (aovar profile); --pruned prints each drop's reason");
  list->add_option("--size", list_profile.size, "frame size the scene is profiled at")->capture_default_str();

  ProfileCli prof;
  std::string prof_manifest = "shader_src/aovar.toml";
  auto* pro = app.add_subcommand("profile", "what a scene needs (depth range, r16f error, radius in pixels, background, "
                                            "flicker, the renderer's buffers) and the variants it can drop");
  pro->add_option("--manifest,-m", prof_manifest, "manifest file")->capture_default_str();
  pro->add_option("--scene,-s", prof.options.scene, "builtin:atrium|spheres|stairs|cornell|... or a mesh file")
      ->capture_default_str();
  pro->add_option("--view", prof.options.views, "only these views (repeatable; default: every view)");
  pro->add_option("--size", prof.size, "frame size the variants will run at")->capture_default_str();
  pro->add_option("--radius", prof.options.radius, "AO radius in scene units (0: the scene's)")->capture_default_str();
  pro->add_option("--r16f-tolerance", prof.options.r16f_tolerance,
                  "keep r16f while its p99 position error is under this share of the radius")->capture_default_str();
  pro->add_option("--threads", prof.options.threads, "threads (Embree, lavapipe)")->capture_default_str();
  pro->add_flag("--no-flicker", prof.no_flicker, "do not render the progressive pair along the camera paths");
  pro->add_flag("--no-cache", prof.no_cache, "compile the flicker pair without the cache");
  pro->add_option("--out,-o", prof.out, "folder for profile.json");

  CommonOptions gen_opts;
  compile::OutputOptions out;
  std::string out_dir, depfile, depfile_target, stamp, emit = "index,source,spirv,cpp";
  auto* gen = app.add_subcommand("generate", "templates -> per-target sources, SPIR-V, variants.json, C++ embedding");
  add_common(gen, gen_opts);
  gen->add_option("--out,-o", out_dir, "output folder")->required();
  gen->add_option("--depfile", depfile, "write a gcc-style depfile listing the manifest and every template read");
  gen->add_option("--depfile-target", depfile_target, "the output the depfile names (default: OUT/variants.json)");
  gen->add_option("--stamp", stamp, "touch this file after a successful run (for build systems)");
  gen->add_option("--emit", emit, "what to write: index,source,spirv,cpp")->capture_default_str();
  gen->add_option("--namespace", out.cpp_namespace, "C++ namespace and file name of the embedding")->capture_default_str();
  gen->add_flag("--check", out.check, "write nothing; exit 1 when any output would change (CI staleness check)");

  CommonOptions measure_common;
  measure::MeasureOptions mo;
  std::string measure_size = "640x360", measure_out, measure_scene = "builtin:atrium", views_file;
  std::vector<std::string> measure_params;
  auto* meas = app.add_subcommand("measure", "render and time variants on a scene through lavapipe / OSMesa");
  add_common(meas, measure_common);
  meas->add_option("--scene,-s", measure_scene, "builtin:atrium|spheres|stairs|cornell or an .obj/.gltf/.glb file")
      ->capture_default_str();
  meas->add_option("--views-file", views_file, "views side file (TOML or JSON) for the scene");
  meas->add_option("--view", mo.views, "view name (repeatable; default: the scene's first view)");
  meas->add_option("--backend,-b", mo.backends, "lavapipe, osmesa (repeatable or comma-separated)")
      ->delimiter(',')->capture_default_str();
  meas->add_option("--size", measure_size, "output size WxH")->capture_default_str();
  meas->add_option("--reps", mo.reps, "timed rounds (min-of-N)")->capture_default_str();
  meas->add_option("--warmup", mo.warmup, "discarded frames after the first (JIT) frame")->capture_default_str();
  meas->add_option("--threads", mo.threads, "LP_NUM_THREADS for llvmpipe")->capture_default_str();
  meas->add_option("--batch", mo.batch, "pipelines prepared and interleaved at once")->capture_default_str();
  meas->add_option("--baseline", mo.baseline, "variant timed in every round (rel_time = 1)")->capture_default_str();
  meas->add_option("--radius", mo.radius, "AO radius in world units (default: the scene's)");
  meas->add_option("--param", measure_params, "override a parameter of the variants that take it: PASS.NAME=VALUE (repeatable)");
  meas->add_option("--out,-o", measure_out, "output folder: measure.json and images/");
  meas->add_flag("--camera-path", mo.camera_path,
                 "frames walk each view's camera path (default: its first pose; the image is the last frame)");
  meas->add_flag("!--no-images", mo.images, "write no PFM/PNG images");
  meas->add_flag("!--no-reuse", mo.reuse, "measure everything again even when OUT/measure.json has the row");
  bool measure_no_prune = false;
  meas->add_flag("--no-prune", measure_no_prune,
                 "measure every selected variant (default: drop, before compiling, those the scene's profile drops)");
  std::string measure_ref_mode = "occlusion", measure_calibration;
  bool no_calibration = false;
  meas->add_flag("--reference", mo.ground_truth,
                 "score every row against a ray-traced reference of its view (error: rmse, mae, psnr, ssim, bias, max)");
  meas->add_option("--rays", mo.reference_rays, "reference rays per pixel (with --reference)")->capture_default_str();
  meas->add_option("--reference-mode", measure_ref_mode, "occlusion or obscurance (with --reference)")
      ->capture_default_str();
  meas->add_option("--calibration", measure_calibration,
                   "calibrated parameters per algorithm (default: calibration.json next to the manifest, when present)");
  meas->add_flag("--no-calibration", no_calibration, "use the manifest's default parameters");

  CommonOptions cal_common;
  calibrate::CalibrateOptions cal;
  std::string cal_size = "320x180", cal_mode = "occlusion", cal_out;
  auto* calc = app.add_subcommand("calibrate",
                                  "fit each method's artistic parameters to ray-traced references (training views), "
                                  "report the error on other views, write a calibration file");
  calc->add_option("--manifest,-m", cal_common.manifest, "manifest file")->capture_default_str();
  calc->add_option("--algorithms", cal.algorithms, "algorithms to fit (comma-separated; default: all)")->delimiter(',');
  calc->add_option("--backend,-b", cal.backend, "lavapipe or osmesa")->capture_default_str();
  calc->add_option("--size", cal_size, "render and reference size WxH")->capture_default_str();
  calc->add_option("--rays", cal.rays, "reference rays per pixel")->capture_default_str();
  calc->add_option("--mode", cal_mode, "reference mode: occlusion or obscurance")->capture_default_str();
  calc->add_option("--evaluations", cal.max_evaluations, "objective evaluations per algorithm")->capture_default_str();
  calc->add_option("--threads", cal.threads, "LP_NUM_THREADS for llvmpipe")->capture_default_str();
  calc->add_option("--out,-o", cal_out, "calibration file to write (e.g. shader_src/calibration.json)")->required();
  calc->add_option("--cache-dir", cal_common.cache_dir, "compile and reference cache (default: $AOVAR_CACHE_DIR or ~/.cache/aovar)");

  CommonOptions ref_common;
  reference::RunOptions ro;
  std::string ref_size = "640x360", ref_mode = "occlusion", ref_scene = "builtin:atrium", ref_views_file, ref_out;
  auto* ref = app.add_subcommand("reference", "ray-trace the ground-truth AO of scene views (Embree)");
  ref->add_option("--scene,-s", ref_scene, "builtin:atrium|spheres|stairs|cornell or an .obj/.gltf/.glb file")
      ->capture_default_str();
  ref->add_option("--views-file", ref_views_file, "views side file (TOML or JSON) for the scene");
  ref->add_option("--view", ro.views, "view name (repeatable; default: the scene's first view)");
  ref->add_option("--radius", ro.radius,
                  "AO radius: world units (0.5) or a percentage of the bounding-box diagonal (1.5%); default: the scene's");
  ref->add_option("--rays", ro.reference.rays, "hemisphere rays per pixel")->capture_default_str();
  ref->add_option("--mode", ref_mode, "occlusion (hit or not) or obscurance (a hit at t occludes 1 - t/radius)")
      ->capture_default_str();
  ref->add_option("--size", ref_size, "output size WxH")->capture_default_str();
  ref->add_option("--threads", ro.reference.threads, "tracing threads (0 = all cores)")->capture_default_str();
  ref->add_option("--frame", ro.reference.frame, "camera-path frame of the view (0 = its first pose)")->capture_default_str();
  ref->add_option("--out,-o", ref_out, "output folder: <view>.pfm, <view>.stderr.pfm, <view>.png, reference.json")
      ->required();
  ref->add_option("--cache-dir", ref_common.cache_dir, "reference cache root (default: $AOVAR_CACHE_DIR or ~/.cache/aovar)");
  ref->add_flag("--no-cache", ref_common.no_cache, "trace everything, read and write no cache");

  std::string analyze_in;
  auto* ana = app.add_subcommand("analyze", "static cost per program and variant of a generated folder (SPIR-V)");
  ana->add_option("--in", analyze_in, "folder written by `aovar generate --emit index,spirv`")->required();

  std::string select_table;
  table::SelectQuery select_query;
  auto* sel = app.add_subcommand("select", "the variant to ship under a time budget or an error target, with the "
                                           "reason, the runners-up and the margin");
  sel->add_option("--table,-t", select_table, "cost_table.json")->required();
  auto* budget = sel->add_option("--budget-ms", select_query.budget_ms, "lowest error with time (time_ms.paired, else min) <= this");
  sel->add_option("--max-error", select_query.max_error, "cheapest variant with error.rmse <= this")->excludes(budget);
  sel->add_option("--tolerance", select_query.tolerance,
                  "name a variant >= 5% cheaper (budget) or with >= 5% less error (max-error) that gives up at most "
                  "this share of the other criterion")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sel->add_option("--scene,-s", select_query.scene, "only this scene (default: all; worst over them)");
  sel->add_option("--view", select_query.view, "only this view (default: each variant's worst view)");
  sel->add_option("--backend,-b", select_query.backend, "only this backend (default: each separately)");

  std::string diff_a, diff_b;
  auto* dif = app.add_subcommand("diff", "per-variant deltas between two cost tables (helped / hurt)");
  dif->add_option("A", diff_a, "the old cost_table.json")->required();
  dif->add_option("B", diff_b, "the new cost_table.json")->required();

  std::string merge_out;
  std::vector<std::string> merge_in;
  auto* mrg = app.add_subcommand("merge", "join shard cost tables into one (refuses conflicting duplicate rows)");
  mrg->add_option("OUT", merge_out, "cost_table.json to write")->required();
  mrg->add_option("IN", merge_in, "shard cost_table.json files")->required();

  std::string report_table, report_out;
  auto* rep = app.add_subcommand("report", "report.md and a self-contained report.html from a cost table");
  rep->add_option("--table,-t", report_table, "cost_table.json (image paths are relative to its folder)")->required();
  rep->add_option("--out,-o", report_out, "output folder (default: the table's folder)");

  StressCli st;
  auto* str = app.add_subcommand("stress", "numerical stability: every variant under extreme cameras, radii, geometry "
                                           "and formats; exit 1 when a shipped variant has NaN, Inf or out-of-range AO");
  add_common(str, st.common);
  str->add_option("--backend,-b", st.options.backends, "lavapipe, osmesa (repeatable or comma-separated)")
      ->delimiter(',')->capture_default_str();
  str->add_option("--size", st.size, "output size WxH")->capture_default_str();
  str->add_option("--threads", st.options.threads, "LP_NUM_THREADS for llvmpipe")->capture_default_str();
  str->add_flag("--shipped", st.options.shipped_only, "only the variants the manifest's [ship] list names");
  str->add_option("--case", st.case_names, "only this default case (repeatable; --list-cases)");
  str->add_flag("--list-cases", st.list_cases, "print the default cases and exit");
  str->add_option("--scene,-s", st.scene, "custom case: scene (with --eye, --target)");
  str->add_option("--eye", st.eye, "custom case: camera position x,y,z");
  str->add_option("--target", st.target, "custom case: point looked at x,y,z");
  str->add_option("--up", st.up, "custom case: up vector x,y,z")->capture_default_str();
  str->add_option("--fov", st.fov, "custom case: vertical field of view, degrees")->capture_default_str();
  str->add_option("--near", st.near_plane, "custom case: near plane")->capture_default_str();
  str->add_option("--far", st.far_plane, "custom case: far plane (inf allowed)")->capture_default_str();
  str->add_option("--radius", st.radius, "custom case: AO radius in scene units (0: the scene's)")->capture_default_str();
  str->add_option("--pair-tolerance", st.options.pair_tolerance,
                  "mediump/highp and r16f/r32f: per-pixel difference beyond which a pixel counts as different")
      ->capture_default_str();
  str->add_option("--pair-share", st.options.pair_share, "share of differing pixels that fails the pair")->capture_default_str();
  str->add_option("--calibration", st.calibration, "calibration file (default: calibration.json next to the manifest)");
  str->add_flag("--no-calibration", st.no_calibration, "use the manifest's default parameters");
  str->add_flag("--no-reuse", st.no_reuse, "check everything again (default: reuse checks whose inputs match OUT/stress.json)");
  str->add_option("--out,-o", st.out, "output folder: stress.json, stress.md");
  str->add_flag("--mediump-fp32", st.mediump_fp32, "run mediump in fp32 on lavapipe (default: real fp16, as mobile GPUs)");
  str->add_option("--renders-per-process", st.options.renders_per_process,
                  "variant x case renders per child process (lavapipe keeps memory per render; 0: render in this process)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();

  CommonOptions sweep_common;
  sweep::SweepOptions so;
  std::string sweep_size = "640x360", sweep_out, sweep_shard, sweep_calibration;
  bool sweep_no_calibration = false;
  auto* swp = app.add_subcommand("sweep", "measure variants on scenes against the ray-traced reference: cost_table.{json,csv,md}");
  add_common(swp, sweep_common);
  swp->add_option("--scene,-s", so.scenes, "scenes (repeatable): builtin:atrium|spheres|stairs|cornell or a mesh file")
      ->capture_default_str();
  swp->add_option("--view", so.measure.views, "view name (repeatable; default: every view of each scene)");
  swp->add_option("--backend,-b", so.measure.backends, "lavapipe, osmesa (repeatable or comma-separated)")
      ->delimiter(',')->capture_default_str();
  swp->add_option("--size", sweep_size, "output size WxH")->capture_default_str();
  swp->add_option("--reps", so.measure.reps, "timed rounds (min-of-N)")->capture_default_str();
  swp->add_option("--threads", so.measure.threads, "LP_NUM_THREADS for llvmpipe")->capture_default_str();
  swp->add_option("--rays", so.measure.reference_rays, "reference rays per pixel")->capture_default_str();
  swp->add_option("--batch", so.measure.batch, "pipelines prepared and interleaved at once (rows are saved per batch)")
      ->capture_default_str();
  swp->add_option("--predict", so.predict,
                  "variants (globs, repeatable) to predict from the cost model instead of measuring: rows marked predicted");
  swp->add_option("--shard", sweep_shard, "k/n: measure only the k-th of n shards of the variants (join with aovar merge)");
  swp->add_option("--calibration", sweep_calibration, "calibration file (default: calibration.json next to the manifest)");
  swp->add_flag("--no-calibration", sweep_no_calibration, "use the manifest's default parameters");
  swp->add_option("--views-file", so.measure.views_file, "views side file (TOML or JSON) for the scene(s)");
  swp->add_option("--warmup", so.measure.warmup, "discarded frames after the first (JIT) frame")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  swp->add_flag("--prune-dominated", so.prune_dominated,
                "measure a first share, then skip the variants the cost model predicts to be dominated");
  swp->add_option("--prune-check", so.prune_check,
                  "with --prune-dominated: measure max(N, a tenth) of the skipped ones anyway, report if any reach the front")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  bool sweep_no_prune = false;
  swp->add_flag("--no-prune", sweep_no_prune,
                "measure every selected variant on every scene (default: drop, before compiling, what each scene's "
                "profile drops)");
  swp->add_option("--out,-o", sweep_out, "output folder: cost_table.{json,csv,md}, measure/<scene>/")->required();

  CLI11_PARSE(app, argc, argv);
  try {
    if (sel->parsed()) return run_select(select_table, select_query);
    if (dif->parsed()) return run_diff(diff_a, diff_b);
    if (mrg->parsed()) return run_merge(merge_out, merge_in);
    if (rep->parsed()) return run_report(report_table, report_out);
    if (str->parsed()) return run_stress(st);
    if (list->parsed())
      return list->count("--scene") ? run_list_scene(list_opts, list_profile, show_pruned) : run_list(list_opts, show_pruned);
    if (pro->parsed()) return run_profile(prof, prof_manifest);
    if (ana->parsed()) return run_analyze(analyze_in);
    if (ref->parsed()) {
      ro.scene = ref_scene;
      ro.views_file = ref_views_file;
      ro.out = ref_out;
      return run_reference(ref_common, ro, ref_size, ref_mode);
    }
    if (meas->parsed()) {
      mo.scene = measure_scene;
      mo.views_file = views_file;
      mo.prune_by_profile = !measure_no_prune;
      return run_measure(measure_common, mo, measure_size, measure_params, measure_out, measure_ref_mode,
                         measure_calibration, no_calibration);
    }
    if (swp->parsed()) {
      so.out = sweep_out;
      so.measure.prune_by_profile = !sweep_no_prune;
      return run_sweep(sweep_common, so, sweep_size, sweep_shard, sweep_calibration, sweep_no_calibration);
    }
    if (calc->parsed()) {
      cal.manifest = cal_common.manifest;
      cal.size = parse_size(cal_size);
      cal.mode = reference::parse_mode(cal_mode);
      return run_calibrate(cal_common, cal, cal_out);
    }
    out.out = out_dir;
    out.emit = 0;
    std::size_t start = 0;
    while (start <= emit.size()) {
      std::size_t end = emit.find(',', start);
      std::string item = emit.substr(start, end == std::string::npos ? std::string::npos : end - start);
      if (item == "index") out.emit |= compile::emit_index;
      else if (item == "source") out.emit |= compile::emit_source;
      else if (item == "spirv") out.emit |= compile::emit_spirv;
      else if (item == "cpp") out.emit |= compile::emit_cpp;
      else throw std::runtime_error("--emit: unknown item '" + item + "' (use index, source, spirv, cpp)");
      if (end == std::string::npos) break;
      start = end + 1;
    }
    if (!depfile.empty()) out.depfile = depfile;
    if (!depfile_target.empty()) out.depfile_target = depfile_target;
    if (!stamp.empty()) out.stamp = stamp;
    return run_generate(gen_opts, out);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
}
