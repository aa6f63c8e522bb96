// The cost table's rows and JSON (cost_table.json), and writing its three files. CSV: csv.cpp; Markdown:
// markdown.cpp; Pareto front and worst view: pareto.cpp.
#include "table/table.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "table/detail.h"
#include "table/validate.h"
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
  if (!j.is_array() || j.size() != 2) throw std::runtime_error("an interval is [lo, hi] or null");
  return {j.at(0).get<double>(), j.at(1).get<double>()};
}

json to_json(const Rounds& r) { return {{"scale", r.scale}, {"id", r.id}, {"ratios", r.ratios}}; }

Rounds rounds_from_json(const json& j) {
  Rounds r{j.at("scale").get<std::string>(), j.at("id").get<std::string>(), j.at("ratios").get<std::vector<double>>()};
  for (double x : r.ratios)
    if (!(x > 0) || !std::isfinite(x)) throw std::runtime_error("a round's ratio must be a positive number");
  return r;
}

namespace {
// The parts of a breakdown by their JSON name, in file order.
struct PartField {
  const char* name;
  metrics::ErrorPart metrics::ErrorBreakdown::*part;
};
constexpr PartField kParts[] = {{"edge", &metrics::ErrorBreakdown::edge},   {"interior", &metrics::ErrorBreakdown::interior},
                                {"near", &metrics::ErrorBreakdown::near},   {"far", &metrics::ErrorBreakdown::far},
                                {"light", &metrics::ErrorBreakdown::light}, {"dark", &metrics::ErrorBreakdown::dark}};

double nan_if_null(const json& j) { return j.is_null() ? std::numeric_limits<double>::quiet_NaN() : j.get<double>(); }
}  // namespace

json to_json(const metrics::ErrorBreakdown& b) {
  json out = {{"edge_band_px", num(b.edge_band_px)}, {"split_depth", num(b.split_depth)}};
  for (const auto& [name, part] : kParts) {
    const metrics::ErrorPart& p = b.*part;
    out[name] = {{"pixel_share", num(p.pixel_share)}, {"rmse", num(p.rmse)}, {"error_share", num(p.error_share)},
                 {"mean_error", num(p.mean_error)}};
  }
  return out;
}

metrics::ErrorBreakdown breakdown_from_json(const json& j) {
  metrics::ErrorBreakdown b;
  b.edge_band_px = nan_if_null(j.at("edge_band_px"));
  b.split_depth = nan_if_null(j.at("split_depth"));
  for (const auto& [name, part] : kParts) {
    const json& p = j.at(name);
    b.*part = {nan_if_null(p.at("pixel_share")), nan_if_null(p.at("rmse")), nan_if_null(p.at("error_share")),
               nan_if_null(p.at("mean_error"))};
  }
  return b;
}

std::string CostRow::key() const {
  return fmt::format("{}|{}|{}|{}|{}|{}", variant, scene, view, backend, size, threads);
}

json to_json(const CostRow& r) {
  json axes = json::object();
  for (const auto& [k, v] : r.axes) axes[k] = v;
  json error = nullptr;
  if (r.error) {
    error = json::object();
    metrics::ErrorStats e = *r.error;
    for (int i = 0; i < 6; ++i) error[kErrorFields[i]] = num(error_field(e, i));
    if (e.breakdown) error["breakdown"] = to_json(*e.breakdown);
  }
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
          {"static", to_json(r.static_cost)},
          {"gpu", to_json(r.gpu)},
          {"time_ms", {{"min", r.time_ms.min}, {"median", r.time_ms.median}, {"p90", r.time_ms.p90}, {"n", r.time_ms.n},
                       {"paired", r.time_ms.paired}, {"paired_ci", to_json(r.time_ms.paired_ci)}}},
          {"rel_time", r.rel_time},
          {"rel_time_median", r.rel_time_median},
          {"rel_time_ci", to_json(r.rel_time_ci)},
          {"rounds", r.rounds.ratios.empty() ? json(nullptr) : to_json(r.rounds)},
          {"same_code_as", r.same_code_as},
          {"error", error},
          {"health", {{"nan", r.health.nan}, {"inf", r.health.inf}, {"out_of_range", r.health.out_of_range}}},
          {"pareto", r.pareto},
          {"predicted", r.predicted},
          {"flicker", r.flicker ? json(*r.flicker) : json(nullptr)},
          {"images", r.images}};
}

CostRow row_from_json(const json& j) {
  CostRow r;
  std::string field = "variant";
  try {
    r.variant = j.at("variant").get<std::string>();
    field = "axes";
    for (const auto& [k, v] : j.at("axes").items()) r.axes[k] = v.is_string() ? v.get<std::string>() : v.dump();
    field = "spirv_hash";
    r.spirv_hash = j.value("spirv_hash", "");
    field = "scene";
    r.scene = j.at("scene").get<std::string>();
    field = "view";
    r.view = j.at("view").get<std::string>();
    field = "backend";
    r.backend = j.at("backend").get<std::string>();
    field = "device";
    r.device = j.value("device", "");
    field = "driver";
    r.driver = j.value("driver", "");
    field = "size";
    r.size = j.value("size", "");
    field = "threads";
    r.threads = j.value("threads", 0);
    field = "static";
    if (j.contains("static")) r.static_cost = static_cost_from_json(j.at("static"));
    field = "gpu";
    if (j.contains("gpu")) r.gpu = gpu_costs_from_json(j.at("gpu"));
    field = "time_ms";
    const json& t = j.at("time_ms");
    r.time_ms = {t.at("min").get<double>(), t.value("median", 0.0), t.value("p90", 0.0), t.value("n", 0),
                 t.value("paired", 0.0)};
    if (t.contains("paired_ci")) r.time_ms.paired_ci = interval_from_json(t.at("paired_ci"));
    field = "rel_time";
    r.rel_time = j.value("rel_time", 0.0);
    field = "rel_time_median";
    r.rel_time_median = j.value("rel_time_median", 0.0);
    field = "rel_time_ci";
    if (j.contains("rel_time_ci")) r.rel_time_ci = interval_from_json(j.at("rel_time_ci"));
    field = "rounds";
    if (j.contains("rounds") && !j.at("rounds").is_null()) r.rounds = rounds_from_json(j.at("rounds"));
    field = "same_code_as";
    r.same_code_as = j.value("same_code_as", "");
    field = "error";
    if (j.contains("error") && !j.at("error").is_null()) {
      metrics::ErrorStats e;
      const json& ej = j.at("error");
      for (int i = 0; i < 6; ++i) {
        const json& v = ej.at(kErrorFields[i]);
        error_field(e, i) = v.is_null() ? std::numeric_limits<double>::infinity() : v.get<double>();
      }
      field = "error.breakdown";  // tables written before it have none
      if (ej.contains("breakdown") && !ej.at("breakdown").is_null()) e.breakdown = breakdown_from_json(ej.at("breakdown"));
      r.error = e;
    }
    field = "health";
    if (j.contains("health")) {
      const json& h = j.at("health");
      r.health.nan = h.value("nan", 0L);
      r.health.inf = h.value("inf", 0L);
      r.health.out_of_range = h.value("out_of_range", 0L);
    }
    field = "pareto";
    r.pareto = j.value("pareto", false);
    field = "predicted";
    r.predicted = j.value("predicted", false);
    field = "flicker";
    if (j.contains("flicker") && !j.at("flicker").is_null()) r.flicker = j.at("flicker").get<double>();
    field = "images";
    if (j.contains("images")) r.images = j.at("images").get<std::vector<std::string>>();
  } catch (const std::exception& e) {  // json's type errors and the checks above
    throw std::runtime_error("row '" + r.variant + "': field '" + field + "': " + e.what());
  }
  return r;
}

json to_json(const CostTable& t) {
  json rows = json::array();
  for (const auto& r : t.rows) rows.push_back(to_json(r));
  return {{"schema_version", util::kSchemaVersion}, {"meta", t.meta}, {"rows", rows}};
}

namespace {

// "meta" as read: an object (absent: an empty one).
json checked_meta(const json& j) {
  if (!j.contains("meta")) return json::object();
  if (!j.at("meta").is_object())
    throw std::runtime_error(fmt::format("\"meta\" is {}, not an object (write {{}} when there is nothing in it)",
                                         j.at("meta").type_name()));
  return j.at("meta");
}

CostRow indexed_row(const json& j, std::size_t index) {
  try {
    return row_from_json(j);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("row {}: {}", index, e.what()));
  }
}

}  // namespace

CostTable table_from_json(const json& j) {
  if (!j.is_object() || !j.contains("rows") || !j.at("rows").is_array())
    throw std::runtime_error("not a cost table (no \"rows\" array)");
  CostTable t;
  t.meta = checked_meta(j);
  const json& rows = j.at("rows");
  t.rows.reserve(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) t.rows.push_back(indexed_row(rows[i], i));
  validate_rows(t.rows);
  return t;
}

namespace {

// The file's rows become CostRows while it is parsed, each row's JSON dropped once read: a DOM of the whole
// document took about 5x the file (7.5 GB for a 1,000,000-row table); this keeps about one row's. A row's
// error waits for the end of the parse: "schema_version" comes after "rows" in the file (keys are sorted),
// and a newer aovar's table must be refused for its version, not for a row this one cannot read.
CostTable parse_streaming(const std::string& text, const std::filesystem::path& path) {
  CostTable t;
  std::string first_error;
  std::string top_key;  // the top-level key whose value is being parsed
  bool rows_array = false;
  std::size_t index = 0;
  json doc = json::parse(text, [&](int depth, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::key && depth == 1) top_key = parsed.get<std::string>();
    if (event == json::parse_event_t::array_start && depth == 1) rows_array = top_key == "rows";
    if (event == json::parse_event_t::array_end && depth == 1) rows_array = false;
    if (event == json::parse_event_t::object_end && depth == 2 && rows_array) {
      if (first_error.empty()) try {
          t.rows.push_back(indexed_row(parsed, index));
        } catch (const std::exception& e) {
          first_error = e.what();
        }
      ++index;
      return false;  // not kept in the document
    }
    return true;
  });
  util::check_schema(doc, path);
  if (!doc.is_object() || !doc.contains("rows") || !doc.at("rows").is_array())
    throw std::runtime_error("not a cost table (no \"rows\" array)");
  if (!first_error.empty()) throw std::runtime_error(first_error);
  if (!doc.at("rows").empty())  // a row that is not an object stays in the array
    throw std::runtime_error(fmt::format("a row is {}, not an object", doc.at("rows").front().type_name()));
  t.meta = checked_meta(doc);
  validate_rows(t.rows);
  return t;
}

}  // namespace

CostTable read_table(const std::filesystem::path& path) {
  auto content = util::read_file(path);
  if (!content) throw std::runtime_error(util::display_path(path) + ": cannot read the cost table");
  try {
    return parse_streaming(*content, path);
  } catch (const util::NewerSchema&) {
    throw;  // already names the file
  } catch (const std::exception& e) {
    throw std::runtime_error(util::display_path(path) + ": " + e.what());
  }
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
