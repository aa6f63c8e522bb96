// The sharded sweep's plan: units, costs, assignment and input hashes (shard_plan.h).
#include "sweep/shard_plan.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "compile/glslang_compiler.h"
#include "scene/scene.h"
#include "shard/manifest.h"
#include "sweep/static_costs.h"
#include "table/table.h"
#include "util/fs.h"
#include "util/hash.h"
#include "variants/key.h"
#include "variants/manifest.h"

namespace aovar::sweep {
namespace {
using json = nlohmann::json;

// Unit id of each variant: its identical variant (same programs and pipeline: measured once), and a mediump
// variant joins its highp twin (llvmpipe runs them as the same code: measure times one, same_code.h), so a
// sharded sweep measures exactly what one process would.
std::map<std::string, std::string> unit_ids(const SweepOptions& o, const std::map<std::string, VariantStatic>& statics) {
  const variants::Manifest& manifest = o.measure.scope.manifest.get();
  std::map<std::string, std::string> ids;
  for (const auto& [key, vs] : statics) {
    std::string twin = key;
    for (const char* highp : {"highp", "hp"})
      if (auto k = variants::with_axis(manifest, key, variants::Axis::precision, highp); k && statics.count(*k)) {
        twin = *k;
        break;
      }
    ids[key] = statics.at(twin).same_as;
  }
  return ids;
}

// Per variant: the time an earlier table spent on it (rounds x median frame over its measured rows).
std::map<std::string, double> earlier_times(const std::filesystem::path& file) {
  const table::CostTable t = table::read_table(file);
  std::map<std::string, double> spent;
  for (const auto& row : t.rows)
    if (!row.predicted && row.time_ms.n > 0) spent[row.variant] += row.time_ms.n * row.time_ms.median;
  return spent;
}

// The static cost of a unit: work per output pixel plus a fixed share per variant (preparing, JIT, reading
// back and scoring cost about as much as an average variant's frames at the sizes swept).
std::vector<shard::Unit> units_by_static_cost(const std::map<std::string, VariantStatic>& statics,
                                              const std::map<std::string, std::string>& ids) {
  double sum = 0;
  for (const auto& [key, vs] : statics) sum += vs.cost.work_per_pixel;
  const double fixed = std::max(1.0, sum / static_cast<double>(std::max<std::size_t>(1, statics.size())));
  std::map<std::string, shard::Unit> by_id;
  for (const auto& [key, vs] : statics) {
    shard::Unit& u = by_id[ids.at(key)];
    u.id = ids.at(key);
    u.members.push_back(key);
    u.cost = std::max(u.cost, vs.cost.work_per_pixel + fixed);  // a unit is measured once
  }
  std::vector<shard::Unit> units;
  for (auto& [id, u] : by_id) units.push_back(std::move(u));
  return units;
}

// --shard-times: each unit's earlier time; units the table lacks get their static cost scaled by the median
// ratio of time to static cost over the units it has.
void apply_times(std::vector<shard::Unit>& units, const std::filesystem::path& file, std::string& costs_from) {
  const auto spent = earlier_times(file);
  std::vector<double> ratios;
  std::vector<double> times(units.size(), 0);
  int known = 0;
  for (std::size_t i = 0; i < units.size(); ++i) {
    for (const auto& key : units[i].members)
      if (auto it = spent.find(key); it != spent.end()) times[i] = std::max(times[i], it->second);
    if (times[i] > 0) {
      ratios.push_back(times[i] / units[i].cost);
      ++known;
    }
  }
  if (ratios.empty())
    throw std::runtime_error(fmt::format("--shard-times {}: none of its measured rows is a selected variant (use the "
                                         "cost_table.json of an earlier sweep of these variants, or leave it out)",
                                         util::display_path(file)));
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  const double scale = ratios[ratios.size() / 2];
  for (std::size_t i = 0; i < units.size(); ++i) units[i].cost = times[i] > 0 ? times[i] : units[i].cost * scale;
  costs_from = fmt::format("times of {} ({} of {} units, the rest by static cost)", util::display_path(file), known,
                           units.size());
}

std::string file_hash(const std::filesystem::path& file) {
  if (file.empty()) return "";
  auto text = util::read_file(file);
  if (!text) throw std::runtime_error(util::display_path(file) + ": cannot read it");
  return util::hash_hex(*text);
}

json input_hashes(const SweepOptions& o, const std::map<std::string, VariantStatic>& statics) {
  const measure::MeasureOptions& m = o.measure;
  util::Hasher programs;  // the templates as compiled: every selected variant's programs
  for (const auto& [key, vs] : statics) programs.add(key).add(vs.vulkan_programs);
  json scenes = json::array();
  for (const auto& s : o.scenes) {
    scene::LoadOptions lo;
    lo.views_file = m.views_file;
    const scene::Scene sc = scene::load_scene(s, lo);  // its views follow from the geometry or the views file
    scenes.push_back({{"scene", s}, {"geometry", sc.content_hash}});
  }
  json options = {{"variants", m.globs}, {"predict", o.predict}, {"views", m.views}, {"backends", m.backends},
                  {"device", m.device}, {"size", fmt::format("{}x{}", m.size.width, m.size.height)},
                  {"reps", measure::reps_text(m)}, {"warmup", m.timing.warmup}, {"threads", m.scope.threads},
                  {"rays", m.truth.rays}, {"radius", m.radius}, {"params", m.params}, {"baseline", m.baseline},
                  {"calibration", m.calibration.hash}, {"profile_prune", o.prune_by_profile},
                  {"prune_dominated", o.prune_dominated}, {"prune_check", o.prune_check},
                  {"min_model_spearman", o.min_model_spearman}, {"gpu", o.gpu.families},
                  {"shard_times", file_hash(o.shard_times)}};
  if (!m.truth.temporal) options["temporal"] = false;  // shards without flicker rows (ship's screen) are another run
  // The estimate's frame and trace change every row's gpu costs: shards must agree on them (issue 33).
  if (!o.gpu.families.empty())
    options["gpu_estimate"] = {{"frame", fmt::format("{}x{}", o.gpu.frame.width, o.gpu.frame.height)},
                               {"trace", o.gpu.trace}, {"window", o.gpu.window}};
  return {{"manifest", m.scope.manifest->hash}, {"templates", programs.hex()}, {"scenes", scenes},
          {"views_file", file_hash(m.views_file)}, {"options", util::hash_hex(options.dump())}};
}

}  // namespace

ShardPlan plan_shards(const SweepOptions& o) {
  std::vector<std::string> globs = o.measure.globs;
  if (!globs.empty()) globs.insert(globs.end(), o.predict.begin(), o.predict.end());
  const auto statics = static_costs(o.measure, globs);
  ShardPlan plan;
  plan.units = units_by_static_cost(statics, unit_ids(o, statics));
  plan.costs_from = "static cost";
  if (!o.shard_times.empty()) apply_times(plan.units, o.shard_times, plan.costs_from);
  plan.assignment = shard::assign(plan.units, o.shard.count);
  const auto mine = shard::members_of(plan.units, plan.assignment, o.shard.index);
  plan.keys = std::make_shared<const std::set<std::string>>(mine.begin(), mine.end());
  plan.inputs = input_hashes(o, statics);
  return plan;
}

void write_sweep_manifest(const SweepOptions& o, const ShardPlan& plan, const std::vector<table::CostRow>& rows,
                          bool complete, double wall_s) {
  shard::ShardManifest m = shard::planned_manifest("sweep", compile::tool_version(), plan.inputs, plan.assignment,
                                                   o.shard.index, o.shard.convention, plan.costs_from);
  m.done = static_cast<int>(rows.size());
  if (complete) {  // pins the table just written: merge refuses it with rows removed or added
    std::vector<std::string> keys;
    for (const auto& r : rows) keys.push_back(r.key());
    m.rows_hash = shard::hash_row_keys(std::move(keys));
  }
  m.complete = complete;
  m.wall_s = wall_s;
  shard::write_manifest(o.out, m);
}

}  // namespace aovar::sweep
