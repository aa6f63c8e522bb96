// The cost table's rows and JSON (cost_table.json), and writing its three files. Reading cost_table.json:
// json_reader.cpp; CSV: csv.cpp; Markdown: markdown.cpp. The Pareto front and worst view are decide/pareto.h.
#include "table/table.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "table/detail.h"
#include "util/fs.h"
#include "util/schema.h"

namespace aovar::table {
namespace {
using json = nlohmann::json;
using detail::error_field;
using detail::kErrorFields;

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

}  // namespace

json to_json(const util::Interval& i) { return i.known() ? json::array({i.lo, i.hi}) : json(nullptr); }

util::Interval interval_from_json(const json& j) {
  if (j.is_null()) return {};
  if (!j.is_array() || j.size() != 2) throw std::runtime_error(detail::kIntervalShape);
  return {j.at(0).get<double>(), j.at(1).get<double>()};
}

json to_json(const Rounds& r) { return {{"scale", r.scale}, {"id", r.id}, {"ratios", r.ratios}}; }

Rounds rounds_from_json(const json& j) {
  Rounds r{j.at("scale").get<std::string>(), j.at("id").get<std::string>(), j.at("ratios").get<std::vector<double>>()};
  detail::check_ratios(r.ratios);
  return r;
}

void detail::check_ratios(const std::vector<double>& ratios) {
  for (double x : ratios)
    if (!(x > 0) || !std::isfinite(x)) throw std::runtime_error("a round's ratio must be a positive number");
}

namespace {
double nan_if_null(const json& j) { return j.is_null() ? std::numeric_limits<double>::quiet_NaN() : j.get<double>(); }
}  // namespace

json to_json(const metrics::ErrorBreakdown& b) {
  json out = {{"edge_band_px", num(b.edge_band_px)}, {"split_depth", num(b.split_depth)}};
  for (const auto& [name, part] : detail::kBreakdownParts) {
    json& p = out[name] = json::object();
    for (const auto& [value_name, value] : detail::kPartValues) p[value_name] = num((b.*part).*value);
  }
  return out;
}

metrics::ErrorBreakdown breakdown_from_json(const json& j) {
  metrics::ErrorBreakdown b;
  b.edge_band_px = nan_if_null(j.at("edge_band_px"));
  b.split_depth = nan_if_null(j.at("split_depth"));
  for (const auto& [name, part] : detail::kBreakdownParts)
    for (const auto& [value_name, value] : detail::kPartValues) (b.*part).*value = nan_if_null(j.at(name).at(value_name));
  return b;
}

std::string CostRow::key() const {
  return fmt::format("{}|{}|{}|{}|{}|{}", variant, scene, view, backend, size, threads);
}

std::optional<TimeSplit> time_split(const CostRow& r) {
  if (!r.gbuffer_ms || !(r.time_ms.median > 0)) return std::nullopt;
  const double frame = r.time_ms.decision(), gbuffer = frame * r.gbuffer_ms->median / r.time_ms.median;
  return TimeSplit{gbuffer, frame - gbuffer};
}

json frame_times_json(const util::TimeStats& s) {
  return {{"min", s.min}, {"median", s.median}, {"p90", s.p90}, {"n", s.n}};
}

json to_json(const metrics::ErrorStats& e) {
  json error = json::object();
  metrics::ErrorStats copy = e;
  for (int i = 0; i < 6; ++i) error[kErrorFields[i]] = num(error_field(copy, i));
  if (e.breakdown) error["breakdown"] = to_json(*e.breakdown);
  return error;
}

json shared_row_json(const CostRow& r) {
  json axes = json::object();
  for (const auto& [k, v] : r.axes) axes[k] = v;
  return {{"variant", r.variant},
          {"axes", axes},
          {"spirv_hash", r.spirv_hash},
          {"scene", r.scene},
          {"view", r.view},
          {"backend", r.backend},
          {"device", r.device},
          {"driver", r.driver},
          {"size", r.size},
          {"threads", r.threads},
          {"gpu", to_json(r.gpu)},
          {"time_ms", frame_times_json(r.time_ms)},
          {"rel_time", r.rel_time},
          {"rel_time_median", r.rel_time_median},
          {"same_code_as", r.same_code_as},
          {"error", r.error ? to_json(*r.error) : json(nullptr)},
          {"health", {{"nan", r.health.nan}, {"inf", r.health.inf}, {"out_of_range", r.health.out_of_range}}},
          {"flicker", r.flicker ? json(*r.flicker) : json(nullptr)}};
}

// cost_table.json's row: the shared fields, the static cost, the paired time's interval, the G-buffer's
// times (null: no measured split; measure.json has them as passes.gbuffer), the rounds (null for rows
// without), the front and the images.
json to_json(const CostRow& r) {
  json j = shared_row_json(r);
  j["time_ms"]["paired"] = r.time_ms.paired;
  j["time_ms"]["paired_ci"] = to_json(r.time_ms.paired_ci);
  j["gbuffer_ms"] = r.gbuffer_ms ? frame_times_json(*r.gbuffer_ms) : json(nullptr);
  j["static"] = to_json(r.static_cost);
  j["rel_time_ci"] = to_json(r.rel_time_ci);
  j["rounds"] = r.rounds.ratios.empty() ? json(nullptr) : to_json(r.rounds);
  j["pareto"] = r.pareto;
  j["predicted"] = r.predicted;
  j["images"] = r.images;
  return j;
}

json to_json(const CostTable& t) {
  json rows = json::array();
  for (const auto& r : t.rows) rows.push_back(to_json(r));
  return {{"schema_version", util::kSchemaVersion}, {"meta", to_json(t.meta)}, {"rows", rows}};
}

void write_json(const CostTable& table, const std::filesystem::path& path) {
  util::write_atomic(path, to_json(table).dump(1) + "\n");
}

void write_table_files(const CostTable& table, const std::filesystem::path& dir) {
  write_json(table, dir / "cost_table.json");
  util::write_atomic(dir / "cost_table.csv", to_csv(table));
  util::write_atomic(dir / "cost_table.md", to_markdown(table));
}

}  // namespace aovar::table
