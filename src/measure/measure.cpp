// `aovar measure`: the run's orchestration. Its pieces: inputs.h (what a row depends on), rows_json.h
// (measure.json and reuse), batch.h (timing a batch against the baseline), contact_sheets.h.
#include "measure/measure.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <numeric>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <malloc.h>
#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "measure/batch.h"
#include "measure/contact_sheets.h"
#include "measure/inputs.h"
#include "measure/rows_json.h"
#include "util/clock.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/hash.h"
#include "util/schema.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace aovar::measure {
namespace fs = std::filesystem;
using json = nlohmann::json;
using util::Clock;
using util::seconds_since;

namespace {

void check_options(const MeasureOptions& o) {
  // An unknown --backend fails here, before the scene's profile renders (the sanitized suite, slow enough to
  // show it, caught the error arriving after a profile's progress line).
  (void)render::targets_of(o.backends);
  if (o.timing.reps < 1) throw std::runtime_error("--reps must be at least 1");
  if (o.timing.auto_reps && !(o.timing.auto_reps->ci_target > 0 && o.timing.auto_reps->cap_s > 0))
    throw std::runtime_error("--reps auto needs --ci-target and --reps-cap-s above 0");
  // The image is each pipeline's last frame, which --reps auto makes differ between rows: the reference
  // traced for a path frame would match none of them.
  if (o.timing.auto_reps && o.timing.camera_path) throw std::runtime_error("--camera-path needs a fixed --reps N, not auto");
  if (o.size.width < 1 || o.size.height < 1) throw std::runtime_error("--size must be WxH with W, H >= 1");
  if (o.timing.races() && !(o.timing.race_margin >= 1.0)) throw std::runtime_error("the race's margin must be a time ratio >= 1");
  if (o.timing.race_scores_stills && !o.truth.enabled)
    throw std::runtime_error("the race scores its stills against the reference: it needs --reference");
}

Selection select_variants(const compile::CompiledSpace& c, const MeasureOptions& o, const ScenePruning* pruning,
                          const Progress& say) {
  Selection s;
  std::map<int, int> representative;  // canonical variant -> the selected variant measured for its group
  auto canonical = [&](int v) { return c.variant_same_as[v] >= 0 ? c.variant_same_as[v] : v; };
  for (int v = 0; v < static_cast<int>(c.space.variants.size()); ++v) {
    const std::string& key = c.space.variants[v].key;
    if (key == o.baseline) s.baseline = v;
    if (!util::glob_any(o.globs, key) || o.skip.count(key) || (pruning && pruning->drops(key))) continue;
    if (!o.in_shard(key)) continue;
    auto [it, fresh] = representative.emplace(canonical(v), v);
    if (fresh) s.measured.push_back(v);
    else s.duplicates[it->second].push_back(key);
  }
  if (s.measured.empty()) return s;
  if (s.baseline < 0) {
    s.baseline = s.measured.front();
    say(fmt::format("note: baseline {} is not in the manifest; using {}", o.baseline, c.space.variants[s.baseline].key));
  } else if (auto it = representative.find(canonical(s.baseline)); it != representative.end()) {
    s.baseline = it->second;  // identical to a selected variant: that one's row is the baseline row
  }
  s.baseline_selected = std::find(s.measured.begin(), s.measured.end(), s.baseline) != s.measured.end();
  if (pruning && pruning->drops(c.space.variants[s.baseline].key))
    say(fmt::format("note: the baseline {} is dropped by the scene's profile: timed as the pairing reference only",
                    c.space.variants[s.baseline].key));
  return s;
}

// Why nothing is left to measure, blaming what emptied it: the manifest's rules, the --variants globs, or
// --skip and the scene's profile (a message about --variants when none was given sent people looking there).
std::string empty_selection(const compile::CompiledSpace& c, const MeasureOptions& o) {
  const std::string where = c.manifest.error_prefix();
  if (c.space.collapsed == 0)
    return fmt::format("{}: the rules drop all {} variants of the space (aovar list --pruned shows which rule drops "
                       "what): loosen a rule",
                       where, c.space.space);
  // The compiled space also holds the baseline: count only the variants the globs select.
  const auto matching = o.globs.empty() ? c.space.variants.size()
                                        : std::size_t(std::count_if(c.space.variants.begin(), c.space.variants.end(),
                                                                    [&](const auto& v) { return util::glob_any(o.globs, v.key); }));
  if (!o.globs.empty() && matching == 0)
    return fmt::format("{}: no variant matches --variants {} (aovar list shows the keys)", where, fmt::join(o.globs, " "));
  return fmt::format("{}: every selected variant ({}{}) is left out by --skip or the scene's profile (aovar list "
                     "--scene shows what the profile drops)",
                     where, matching, o.globs.empty() ? "" : " matching --variants " + fmt::format("{}", fmt::join(o.globs, " ")));
}

// --param: each override must be a parameter of at least one selected variant (variants without it, e.g.
// blur.radius_px on an unblurred one, simply do not take it) and inside the manifest's [min, max] for it
// (the shaders and the stress suite assume the range; calibration files are checked the same way).
void check_params(const variants::Manifest& manifest, const variants::VariantSpace& space, const std::vector<int>& selected,
                  const render::ParamOverrides& params) {
  std::map<std::string, const variants::Param*> parameters;
  for (int v : selected) {
    const auto& entry = space.variants.at(v);
    for (std::size_t i = 0; i < manifest.passes.size(); ++i)
      for (int program : entry.passes[i])
        if (program >= 0)
          for (const auto& param : space.programs[program].params)
            parameters.emplace(manifest.passes[i].name + "." + param.name, &param);
  }
  for (const auto& [key, value] : params) {
    auto p = parameters.find(key);
    if (p == parameters.end()) {
      std::vector<std::string> names;
      for (const auto& [name, param] : parameters) names.push_back(name);
      throw std::runtime_error(fmt::format("--param {}: no selected variant has this parameter (they have: {})", key,
                                           fmt::join(names, ", ")));
    }
    const variants::Param& param = *p->second;
    if (!(value >= param.min && value <= param.max))
      throw std::runtime_error(fmt::format("--param {}={}: outside the range [{}, {}] that {}:{} gives it (pass a value "
                                           "inside it, or widen min/max in the manifest)",
                                           key, value, param.min, param.max, manifest.error_prefix(),
                                           param.pos.line));
  }
}

}  // namespace

void check_request(const MeasureOptions& o) {
  check_options(o);
  if (o.params.empty()) return;
  // The selection as compile will see it (the baseline too): a bad --param fails here, not after the profile.
  std::vector<std::string> globs = o.globs;
  if (!globs.empty()) globs.push_back(o.baseline);
  const variants::Manifest& manifest = o.scope.manifest.get();
  const variants::VariantSpace space = variants::build_space(manifest, globs);
  std::vector<int> all(space.variants.size());
  std::iota(all.begin(), all.end(), 0);
  check_params(manifest, space, all, o.params);
}

std::vector<const scene::View*> chosen_views(const scene::Scene& sc, const std::vector<std::string>& names) {
  std::vector<const scene::View*> views;
  if (names.empty()) views.push_back(&sc.views.front());
  for (const auto& name : names)
    if (std::none_of(views.begin(), views.end(), [&](const scene::View* v) { return v->name == name; }))
      views.push_back(&sc.view(name));
  return views;
}

std::shared_ptr<const ScenePruning> prune_by_profile(const MeasureOptions& o, const scene::Scene& scene,
                                                     const std::vector<std::string>& covered, const Progress& progress) {
  profile::PruneOptions p;
  p.profile.scope = o.scope;
  p.profile.scene = o.scene;
  p.profile.size = o.size;
  p.profile.radius = o.radius;
  p.store_dir = o.out;
  p.reuse = o.reuse;
  return std::make_shared<const ScenePruning>(
      profile::prune_scene(p, scene, chosen_views(scene, o.views), covered, progress));
}

reference::ReferenceOptions reference_options(const MeasureOptions& o, float radius) {
  reference::ReferenceOptions ro;
  ro.size = o.size;
  ro.radius = radius;
  ro.rays = o.truth.rays;
  ro.mode = o.truth.mode;
  ro.frame = o.timing.camera_path ? o.timing.warmup + o.timing.reps : 0;
  ro.cache_dir = o.scope.cache_dir;
  return ro;
}

trace::RowGpuRequest gpu_request(const MeasureOptions& o, const trace::GpuEstimateOptions& gpu) {
  return {o.scope, gpu, o.views_file, o.radius, o.calibration.values};
}

namespace {

class MeasureRun {
 public:
  MeasureRun(const MeasureOptions& o, const Progress& progress) : o_(o), progress_(progress) {}
  MeasureResult run();

 private:
  void say(const std::string& s) const { if (progress_) progress_(s); }
  bool prune(compile::CompileOptions& co);
  void finish();
  void write() const {
    if (!o_.out.empty()) util::write_atomic(o_.out / "measure.json", to_json(res_, o_).dump(1) + "\n");
  }

  const MeasureOptions& o_;
  Progress progress_;
  Clock::time_point start_ = Clock::now();
  MeasureResult res_;
  scene::Scene scene_;
  PreviousRun earlier_;
};

// What the scene's profile drops is not compiled (the baseline, the pairing reference, is timed anyway).
// Returns false when it drops every selected variant: the run then ends with the log of what was dropped.
bool MeasureRun::prune(compile::CompileOptions& co) {
  if (!o_.pruning) return true;
  res_.pruning = o_.pruning;
  const ScenePruning& pr = *res_.pruning;
  say(pr.summary(o_.globs) + (pr.reused ? " (profile reused)" : fmt::format(" (profiled in {:.1f} s)", pr.seconds)));
  bool dropped = false;
  for (const auto& d : pr.dropped)
    if (util::glob_any(o_.globs, d.variant)) {
      dropped = true;
      if (d.variant != o_.baseline) co.exclude.insert(d.variant);
    }
  if (!dropped || std::any_of(pr.kept.begin(), pr.kept.end(), [&](const std::string& k) { return util::glob_any(o_.globs, k); }))
    return true;
  // Nothing left to measure: the log of what was dropped, and the earlier rows kept for later runs.
  say(fmt::format("note: scene {} drops every selected variant: nothing to measure (--no-prune measures them)", o_.scene));
  res_.counts = "every selected variant dropped by the scene's profile";
  res_.kept_rows = json::array();
  if (o_.reuse && !o_.out.empty())
    for (const auto& [hash, j] : read_previous(o_.out, false, progress_).text) res_.kept_rows.push_back(j);
  res_.wall_s = seconds_since(start_);
  write();
  return false;
}

MeasureResult MeasureRun::run() {
  keep_heap_mapped();
  check_request(o_);
  scene::LoadOptions load;
  load.views_file = o_.views_file;
  scene_ = scene::load_scene(o_.scene, load);
  const auto views = chosen_views(scene_, o_.views);
  res_.scene = scene_.name;
  res_.scene_hash = scene_.content_hash;
  res_.triangles = scene_.triangle_count();
  res_.radius = o_.radius > 0 ? o_.radius : scene_.ao_radius;

  // Compile what the backends need (the baseline variant too, when globs would leave it out).
  compile::CompileOptions co{o_.scope};
  co.scope.targets = render::targets_of(o_.backends);  // what the backends render, whatever the scope's targets
  co.globs = o_.globs;
  if (!co.globs.empty()) co.globs.push_back(o_.baseline);
  if (!prune(co)) return std::move(res_);
  auto compile_start = Clock::now();
  compile::CompiledSpace c = compile::compile_space(co);
  res_.compile_s = seconds_since(compile_start);
  if (!c.ok())
    throw std::runtime_error(fmt::format("{} (and {} more diagnostics): fix the templates first (aovar generate shows all)",
                                         c.diagnostics.empty() ? "compile failed" : c.diagnostics.front(),
                                         c.diagnostics.empty() ? 0 : c.diagnostics.size() - 1));

  Selection sel = select_variants(c, o_, res_.pruning.get(), progress_);
  if (sel.measured.empty() && o_.shard_keys) {
    say("note: this shard holds none of the selected variants");
    return std::move(res_);
  }
  if (sel.measured.empty()) throw std::runtime_error(empty_selection(c, o_));
  check_params(c.manifest, c.space, sel.measured, o_.params);
  res_.counts = compile::counts_line(c);

  if (!o_.out.empty()) util::remove_stale_temps(o_.out);  // what a killed earlier run was writing
  earlier_ = o_.reuse && !o_.out.empty() ? read_previous(o_.out, o_.images, progress_) : PreviousRun{};
  BatchMeasurer measurer(o_, c, scene_, sel, earlier_, res_, progress_);
  res_.kept_rows = json::array();
  for (const auto& [hash, j] : measurer.unproduced_rows(views)) res_.kept_rows.push_back(j);
  measurer.measure_all(views, [&] {
    res_.wall_s = seconds_since(start_);
    write();  // after every batch: an interruption loses at most one batch
  });
  if (o_.truth.enabled && o_.images && !o_.out.empty()) measurer.store_references(views);  // the sheets lead with them
  finish();
  return std::move(res_);
}

void MeasureRun::finish() {
  std::stable_sort(res_.rows.begin(), res_.rows.end(), [](const MeasureRow& a, const MeasureRow& b) {
    return std::tie(a.backend, a.view, a.variant) < std::tie(b.backend, b.view, b.variant);
  });
  pair_times(res_.rows);
  // Composing the sheets reads every image again: not when the sheets on disk already show these rows.
  const std::string shown = rows_fingerprint(res_.rows);
  bool current = !earlier_.contact_sheets.empty() && earlier_.contact_sheets_rows == shown &&
                 std::all_of(earlier_.contact_sheets.begin(), earlier_.contact_sheets.end(),
                             [&](const std::string& f) { return fs::exists(o_.out / f); });
  if (current || !o_.contact_sheets) {  // without sheets of its own, a run leaves the earlier ones listed
    res_.contact_sheets = earlier_.contact_sheets;
    res_.contact_sheets_rows = earlier_.contact_sheets_rows;
  } else if (!o_.out.empty() && o_.images) {
    res_.contact_sheets = write_contact_sheets(res_.rows, o_.out);
    res_.contact_sheets_rows = shown;
  }
  res_.wall_s = seconds_since(start_);
  write();
}

// The scene profile's pruning: every selected variant it drops with its rule and reason (null: not pruned).
json pruned_json(const MeasureResult& res, const MeasureOptions& o) {
  if (!res.pruning) return nullptr;
  json j = res.pruning->to_json(o.globs);
  j["profile"] = res.pruning->profile_file;
  j["profile_reused"] = res.pruning->reused;
  j["seconds"] = res.pruning->seconds;
  return j;
}

}  // namespace

void keep_heap_mapped() {
  // llvmpipe allocates and frees large vertex-setup buffers on every geometry draw. With glibc's default
  // thresholds those come from fresh mmaps or are trimmed back to the OS each time, so each frame pays
  // page faults again and G-buffer times jump 2-4x at random (atrium: 5.3 ms alone, 13-20 ms between AO
  // passes). Keeping freed memory in the heap removes that noise from every backend alike.
  static const bool once = [] {
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    return true;
  }();
  (void)once;
}

void MeasureRow::list_images() {
  images.clear();
  for (const std::string* f : {&image, &preview, &error_map})
    if (!f->empty()) images.push_back(*f);
}

void MeasureRow::set_passes(std::vector<std::pair<std::string, util::TimeStats>> per_group) {
  passes = std::move(per_group);
  gbuffer_ms.reset();
  for (const auto& [group, stats] : passes)
    if (group == "gbuffer" && stats.n > 0) gbuffer_ms = stats;
}

std::vector<table::CostRow> cost_rows(const MeasureResult& result, const fs::path& prefix) {
  std::vector<table::CostRow> rows;
  for (const MeasureRow& m : result.rows) {
    // A baseline measured only for timing (not selected) is not a row of the table (another shard owns it),
    // but it scaled every row's paired time.
    if (m.is_baseline) continue;
    table::CostRow r = m;
    for (auto& image : r.images) image = (prefix / image).generic_string();
    rows.push_back(std::move(r));
  }
  return rows;
}

MeasureResult run_measure(const MeasureOptions& options, const Progress& progress) {
  return MeasureRun(options, progress).run();
}

json calibration_json(const MeasureOptions& o) {
  if (o.calibration.file.empty()) return nullptr;
  return {{"file", o.calibration.file}, {"hash", o.calibration.hash}, {"values", o.calibration.values}};
}

json to_json(const MeasureResult& res, const MeasureOptions& o) {
  json devices = json::array();
  for (const auto& d : res.devices)
    devices.push_back({{"backend", d.backend}, {"device", d.device}, {"api", d.api_version}, {"driver", d.driver},
                       {"threads", d.threads}, {"timing", d.timing},
                       {"precision", d.precision}});
  json runs = json::array();
  for (const auto& r : res.runs)
    runs.push_back({{"backend", r.backend}, {"view", r.view}, {"pipelines", r.pipelines}, {"device", r.device},
                    {"prepare_s", r.prepare_s},
                    {"warmup_s", r.warmup_s}, {"timed_wall_s", r.timed_wall_s}, {"timed_sum_s", r.timed_sum_s},
                    {"readback_s", r.readback_s}});
  json rows = json::array();
  for (const auto& r : res.rows) rows.push_back(row_to_json(r, res));
  return {{"schema_version", util::kSchemaVersion},
          {"tool", "aovar measure"},
          {"scene", {{"name", res.scene}, {"hash", res.scene_hash}, {"triangles", res.triangles}}},
          {"manifest", util::display_path(o.scope.manifest.path())},
          {"counts", res.counts},
          {"contact_sheets", res.contact_sheets},
          {"contact_sheets_rows", res.contact_sheets_rows},
          {"size", fmt::format("{}x{}", o.size.width, o.size.height)},
          {"reps", o.timing.reps},
          {"reps_auto", reps_auto_json(o)},
          {"reps_reached", reps_reached(res).to_json()},
          {"warmup", o.timing.warmup},
          {"threads", o.scope.threads},
          {"radius", res.radius},
          {"calibration", calibration_json(o)},
          {"camera_path", o.timing.camera_path},
          {"devices", devices},
          {"runs", runs},
          {"wall_s", res.wall_s},
          {"compile_s", res.compile_s},
          {"reused", res.reused},
          {"rows", rows},
          {"kept_rows", res.kept_rows.is_null() ? json::array() : res.kept_rows},  // null: returned before selecting
          {"pruned", pruned_json(res, o)},
          {"gpu", res.gpu_meta}};
}

}  // namespace aovar::measure
