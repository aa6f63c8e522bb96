// A cost table's typed header, read from and written to cost_table.json's "meta".
#include "table/sweep_meta.h"

#include <fmt/format.h>

#include <stdexcept>
#include <type_traits>

namespace aovar::table {

using json = nlohmann::json;

namespace {

PrunedByProfile pruned_from_json(const json& j) {
  PrunedByProfile p;
  p.selection = pruning_counts_from_json(j);
  p.profile = j.value("profile", std::string());
  if (j.contains("predict")) p.predict = pruning_counts_from_json(j.at("predict"));
  return p;
}

json to_json(const MeasuredScene& s) {
  return {{"scene", s.scene}, {"measure", s.measure}, {"hash", s.hash}, {"radius", s.radius}};
}

MeasuredScene scene_from_json(const json& j) {
  return {j.at("scene").get<std::string>(), j.value("measure", std::string()), j.value("hash", std::string()),
          j.value("radius", 0.0)};
}

// Takes `key` out of `rest` (what is left becomes `other`) and converts it; a wrong type names the key.
template <class Convert>
auto take(json& rest, const char* key, Convert convert) -> std::optional<decltype(convert(json()))> {
  auto it = rest.find(key);
  if (it == rest.end()) return std::nullopt;
  json value = std::move(*it);
  rest.erase(it);
  try {
    return convert(value);
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("meta.{}: {}", key, e.what()));
  }
}

template <class T>
std::optional<T> take(json& rest, const char* key) {
  return take(rest, key, [](const json& v) { return v.get<T>(); });
}

// The array under `key` read item by item with `read` (a list of records); nothing when absent.
template <class Read>
auto take_each(json& rest, const char* key, Read read) {
  return take(rest, key, [&](const json& v) {
    std::vector<std::invoke_result_t<Read, const json&>> out;
    for (const auto& item : v) out.push_back(read(item));
    return out;
  });
}

json take_section(json& rest, const char* key) {
  return take(rest, key, [](const json& v) { return v; }).value_or(json(nullptr));
}

template <class T>
void put(json& j, const char* key, const std::optional<T>& v) {
  if (v) j[key] = *v;
}

// A list of records as the array of their to_json; nothing when the header has none.
template <class T>
void put_each(json& j, const char* key, const std::optional<std::vector<T>>& list) {
  if (!list) return;
  j[key] = json::array();
  for (const auto& item : *list) j[key].push_back(to_json(item));
}

}  // namespace

json to_json(const PrunedByProfile& p) {
  json j = to_json(p.selection);
  if (!p.profile.empty()) j["profile"] = p.profile;
  if (p.predict) j["predict"] = to_json(*p.predict);
  return j;
}

json to_json(const SweepMeta& m) {
  json j = m.other;
  put(j, "tool", m.tool);
  put(j, "manifest", m.manifest);
  put(j, "manifest_hash", m.manifest_hash);
  put_each(j, "scenes", m.scenes);
  put(j, "backends", m.backends);
  put(j, "size", m.size);
  put(j, "reps", m.reps);
  put(j, "rays", m.rays);
  put(j, "calibrated", m.calibrated);
  if (m.calibration) {
    j["calibration"] = nullptr;
    if (const auto& c = *m.calibration) j["calibration"] = {{"hash", c->hash}, {"values", c->values}};
    if (const auto& c = *m.calibration; c && !c->file.empty()) j["calibration"]["file"] = c->file;  // merge drops it
  }
  put(j, "shard", m.shard);
  put(j, "profile_prune", m.profile_prune);
  put_each(j, "pruned", m.pruned);
  put(j, "merged_from", m.merged_from);
  put(j, "shards", m.shards);
  if (m.cost_models) j["cost_models"] = to_json(*m.cost_models);
  put(j, "reps_auto", m.reps_auto);
  for (const auto& [key, section] : {std::pair{"reps_reached", &m.reps_reached},
                                     {"prune", &m.prune}, {"gpu", &m.gpu}, {"ship", &m.ship}})
    if (!section->is_null()) j[key] = *section;
  return j;
}

SweepMeta sweep_meta_from_json(const json& meta) {
  if (!meta.is_object()) throw std::runtime_error(fmt::format("\"meta\" is {}, not an object", meta.type_name()));
  json rest = meta;
  SweepMeta m;
  m.tool = take<std::string>(rest, "tool");
  m.manifest = take<std::string>(rest, "manifest");
  m.manifest_hash = take<std::string>(rest, "manifest_hash");
  m.scenes = take_each(rest, "scenes", scene_from_json);
  m.backends = take<std::vector<std::string>>(rest, "backends");
  m.size = take<std::string>(rest, "size");
  m.reps = take<int>(rest, "reps");
  m.rays = take<int>(rest, "rays");
  m.calibrated = take<bool>(rest, "calibrated");
  m.calibration = take(rest, "calibration", [](const json& v) -> std::optional<CalibrationRef> {
    if (v.is_null()) return std::nullopt;
    return CalibrationRef{v.value("file", std::string()), v.at("hash").get<std::string>(),
                          v.value("values", variants::CalibratedValues{})};
  });
  m.shard = take<std::string>(rest, "shard");
  m.profile_prune = take<bool>(rest, "profile_prune");
  m.pruned = take_each(rest, "pruned", pruned_from_json);
  m.merged_from = take<std::vector<std::string>>(rest, "merged_from");
  m.shards = take<int>(rest, "shards");
  m.reps_auto = take<json>(rest, "reps_auto");
  m.reps_reached = take_section(rest, "reps_reached");
  m.cost_models = take(rest, "cost_models", model_fits_from_json);
  m.prune = take_section(rest, "prune");
  m.gpu = take_section(rest, "gpu");
  m.ship = take_section(rest, "ship");
  m.other = std::move(rest);
  return m;
}

}  // namespace aovar::table
