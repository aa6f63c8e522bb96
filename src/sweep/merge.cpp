// aovar merge: check the shard set, join the tables, refit the per-shard parts (merge.h).
#include "sweep/merge.h"
#include "util/output_apart.h"

#include <set>
#include <stdexcept>

#include "decide/pareto.h"
#include "shard/manifest.h"
#include "sweep/cost_models.h"
#include "table/merge.h"
#include "util/fs.h"

namespace aovar::sweep {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// A shard's images are relative to its folder; the merged table's must be relative to its own.
void rebase_images(table::CostTable& t, const fs::path& from_dir, const fs::path& to_dir) {
  const fs::path from = fs::absolute(from_dir), to = fs::absolute(to_dir);
  for (auto& row : t.rows)
    for (auto& image : row.images) image = (from / image).lexically_normal().lexically_relative(to).generic_string();
}

// The shards' --gpu meta as one run's: the estimate's settings are the same in every shard (the shard manifest's
// options hash holds them), its counts and seconds are each shard's own, so they add up; errors concatenate.
// Counts stay whole numbers, seconds add as reals.
void add_to(json& v, const json& other) {
  if (v.is_number_integer() && other.is_number_integer()) v = v.get<int64_t>() + other.get<int64_t>();
  else if (v.is_number() && other.is_number()) v = v.get<double>() + other.get<double>();
}

json merged_gpu_meta(const std::vector<json>& metas) {
  json out = metas.front();
  for (std::size_t i = 1; i < metas.size(); ++i) {
    for (auto& [k, v] : out.items())
      if (metas[i].contains(k)) add_to(v, metas[i][k]);
    if (out.contains("trace") && metas[i].contains("trace"))
      for (auto& [k, v] : out["trace"].items())
        if (k != "window_share" && metas[i]["trace"].contains(k)) add_to(v, metas[i]["trace"][k]);
    for (const auto& e : metas[i].value("errors", json::array())) out["errors"].push_back(e);
  }
  return out;
}

}  // namespace

MergeResult merge_shards(const std::vector<fs::path>& inputs, const fs::path& out) {
  util::check_output_apart_from_inputs(out, inputs, "merge");
  std::vector<fs::path> dirs, tables;
  std::vector<std::pair<std::string, shard::ShardManifest>> shards;
  std::vector<std::string> plain;  // inputs without a manifest
  for (const auto& in : inputs) {
    const bool folder = fs::is_directory(in);
    dirs.push_back(folder ? in : (in.has_parent_path() ? in.parent_path() : fs::path(".")));
    tables.push_back(folder ? in / "cost_table.json" : in);
    if (fs::exists(dirs.back() / shard::kManifestFile))
      shards.emplace_back(util::display_path(dirs.back()), shard::read_manifest(dirs.back() / shard::kManifestFile));
    else
      plain.push_back(util::display_path(in));
  }
  MergeResult res;
  if (!shards.empty()) {
    if (!plain.empty())
      throw std::runtime_error("merge: " + plain.front() + " has no " + shard::kManifestFile +
                               " next to it while other inputs are shards: merge only the shards of one sharded run");
    shard::check_shard_set(shards);  // before the tables: an incomplete shard may have none yet
    res.shards = static_cast<int>(shards.size());
    res.balance = shard::balance_summary(shards);
  }
  std::vector<std::pair<std::string, table::CostTable>> read;
  std::vector<table::MeasuredScene> scenes;
  std::set<std::string> seen_scenes;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    read.emplace_back(util::display_path(tables[i]), table::read_table(tables[i]));
    if (!shards.empty()) {  // every input is a shard (checked above), in input order
      std::vector<std::string> keys;
      for (const auto& r : read.back().second.rows) keys.push_back(r.key());
      shard::check_pinned_rows(shards[i].first, shards[i].second, read.back().first, keys);
    }
    rebase_images(read.back().second, dirs[i], out.has_parent_path() ? out.parent_path() : fs::path("."));
    for (const auto& s : read.back().second.meta.scenes.value_or(std::vector<table::MeasuredScene>{}))
      if (seen_scenes.insert(s.scene).second) scenes.push_back(s);
  }
  // Shards checked by their manifests each have their own cost models, scenes list (a shard may hold no
  // variant of a scene) and pruning counts; plain tables must agree in all of them as before.
  const std::vector<std::string> per_shard =
      shards.empty() ? std::vector<std::string>{} : std::vector<std::string>{"cost_models", "prune", "scenes", "gpu"};
  std::vector<json> gpu;
  for (const auto& [name, t] : read)
    if (t.meta.gpu.is_object()) gpu.push_back(t.meta.gpu);
  res.table = table::merge_tables(std::move(read), per_shard);
  decide::mark_pareto(res.table);  // the merged table's front, not any shard's
  if (!shards.empty()) {
    if (!gpu.empty()) res.table.meta.gpu = merged_gpu_meta(gpu);
    res.table.meta.scenes = scenes;
    res.table.meta.cost_models = fit_group_models(res.table.rows).models;
    res.table.meta.shards = res.shards;
  }
  return res;
}

}  // namespace aovar::sweep
