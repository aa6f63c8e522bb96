#include "table/table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "util/fs.h"

namespace aovar::table {
namespace {
using json = nlohmann::json;

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{}", v);
}

double parse_double(const std::string& s, const std::string& column) {
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size()) throw std::runtime_error("column '" + column + "': not a number: '" + s + "'");
  return v;
}

const char* kErrorFields[] = {"rmse", "mae", "psnr", "ssim", "bias", "max"};
double& error_field(metrics::ErrorStats& e, int i) {
  double* f[] = {&e.rmse, &e.mae, &e.psnr, &e.ssim, &e.bias, &e.max};
  return *f[i];
}

}  // namespace

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
  }
  return {{"variant", r.variant},
          {"axes", axes},
          {"spirv_hash", r.spirv_hash},
          {"scene", r.scene},
          {"view", r.view},
          {"backend", r.backend},
          {"size", r.size},
          {"threads", r.threads},
          {"static", to_json(r.static_cost)},
          {"time_ms", {{"min", r.time_ms.min}, {"median", r.time_ms.median}, {"p90", r.time_ms.p90}, {"n", r.time_ms.n},
                       {"paired", r.time_ms.paired}}},
          {"rel_time", r.rel_time},
          {"rel_time_median", r.rel_time_median},
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
    field = "size";
    r.size = j.value("size", "");
    field = "threads";
    r.threads = j.value("threads", 0);
    field = "static";
    if (j.contains("static")) r.static_cost = static_cost_from_json(j.at("static"));
    field = "time_ms";
    const json& t = j.at("time_ms");
    r.time_ms = {t.at("min").get<double>(), t.value("median", 0.0), t.value("p90", 0.0), t.value("n", 0),
                 t.value("paired", 0.0)};
    field = "rel_time";
    r.rel_time = j.value("rel_time", 0.0);
    field = "rel_time_median";
    r.rel_time_median = j.value("rel_time_median", 0.0);
    field = "error";
    if (j.contains("error") && !j.at("error").is_null()) {
      metrics::ErrorStats e;
      const json& ej = j.at("error");
      for (int i = 0; i < 6; ++i) {
        const json& v = ej.at(kErrorFields[i]);
        error_field(e, i) = v.is_null() ? std::numeric_limits<double>::infinity() : v.get<double>();
      }
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
  } catch (const json::exception& e) {
    throw std::runtime_error("row '" + r.variant + "': field '" + field + "': " + e.what());
  }
  return r;
}

json to_json(const CostTable& t) {
  json rows = json::array();
  for (const auto& r : t.rows) rows.push_back(to_json(r));
  return {{"meta", t.meta}, {"rows", rows}};
}

CostTable table_from_json(const json& j) {
  if (!j.is_object() || !j.contains("rows") || !j.at("rows").is_array())
    throw std::runtime_error("not a cost table (no \"rows\" array)");
  CostTable t;
  if (j.contains("meta")) t.meta = j.at("meta");
  for (const auto& r : j.at("rows")) t.rows.push_back(row_from_json(r));
  return t;
}

CostTable read_table(const std::filesystem::path& path) {
  auto content = util::read_file(path);
  if (!content) throw std::runtime_error(util::display_path(path) + ": cannot read the cost table");
  try {
    return table_from_json(json::parse(*content));
  } catch (const std::exception& e) {
    throw std::runtime_error(util::display_path(path) + ": " + e.what());
  }
}

void write_json(const CostTable& table, const std::filesystem::path& path) {
  util::write_atomic(path, to_json(table).dump(1) + "\n");
}

// ---- CSV ----

std::string csv_field(const std::string& f) {
  if (f.find_first_of(",\"\r\n") == std::string::npos) return f;
  std::string out = "\"";
  for (char c : f) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::vector<std::vector<std::string>> parse_csv(const std::string& s) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    char c = s[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < s.size() && s[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        field += c;
      }
      continue;
    }
    any = true;
    if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      row.push_back(std::move(field));
      field.clear();
    } else if (c == '\r' || c == '\n') {
      if (c == '\r' && i + 1 < s.size() && s[i + 1] == '\n') ++i;
      row.push_back(std::move(field));
      field.clear();
      rows.push_back(std::move(row));
      row.clear();
      any = false;
    } else {
      field += c;
    }
  }
  if (quoted) throw std::runtime_error("CSV: unterminated quoted field");
  if (any) {
    row.push_back(std::move(field));
    rows.push_back(std::move(row));
  }
  return rows;
}

namespace {
const std::vector<std::string> kFixedHead = {"variant"};
const std::vector<std::string> kFixedTail = {
    "spirv_hash", "scene", "view", "backend", "size", "threads", "time_ms.min", "time_ms.median", "time_ms.p90",
    "time_ms.n", "time_ms.paired", "rel_time", "rel_time_median", "error.rmse", "error.mae", "error.psnr", "error.ssim", "error.bias", "error.max",
    "health.nan", "health.inf", "health.out_of_range", "pareto", "predicted", "flicker", "images", "static"};
}  // namespace

std::string to_csv(const CostTable& t) {
  std::set<std::string> axis_names;
  for (const auto& r : t.rows)
    for (const auto& [k, v] : r.axes) axis_names.insert(k);
  std::vector<std::string> header = kFixedHead;
  for (const auto& a : axis_names) header.push_back("axes." + a);
  header.insert(header.end(), kFixedTail.begin(), kFixedTail.end());
  std::string out;
  auto line = [&](const std::vector<std::string>& fields) {
    for (std::size_t i = 0; i < fields.size(); ++i) out += (i ? "," : "") + csv_field(fields[i]);
    out += "\r\n";  // RFC 4180 line break
  };
  line(header);
  for (const auto& r : t.rows) {
    std::vector<std::string> f = {r.variant};
    for (const auto& a : axis_names) {
      auto it = r.axes.find(a);
      f.push_back(it == r.axes.end() ? "" : it->second);
    }
    std::string images;
    for (std::size_t i = 0; i < r.images.size(); ++i) images += (i ? ";" : "") + r.images[i];
    auto e = [&](int i) {
      if (!r.error) return std::string();
      metrics::ErrorStats copy = *r.error;
      return text(error_field(copy, i));
    };
    std::vector<std::string> tail = {r.spirv_hash, r.scene, r.view, r.backend, r.size, std::to_string(r.threads),
                                     text(r.time_ms.min), text(r.time_ms.median), text(r.time_ms.p90),
                                     std::to_string(r.time_ms.n), text(r.time_ms.paired), text(r.rel_time), text(r.rel_time_median), e(0), e(1), e(2), e(3), e(4), e(5),
                                     std::to_string(r.health.nan), std::to_string(r.health.inf),
                                     std::to_string(r.health.out_of_range), r.pareto ? "true" : "false",
                                     r.predicted ? "true" : "false", r.flicker ? text(*r.flicker) : "", images,
                                     r.static_cost ? to_json(r.static_cost).dump() : std::string("{}")};
    f.insert(f.end(), tail.begin(), tail.end());
    line(f);
  }
  return out;
}

CostTable from_csv(const std::string& s) {
  auto rows = parse_csv(s);
  if (rows.empty()) throw std::runtime_error("CSV: no header line");
  const auto& header = rows[0];
  CostTable t;
  for (std::size_t l = 1; l < rows.size(); ++l) {
    const auto& f = rows[l];
    if (f.size() != header.size())
      throw std::runtime_error(fmt::format("CSV line {}: {} fields, the header has {}", l + 1, f.size(), header.size()));
    std::map<std::string, std::string> c;
    for (std::size_t i = 0; i < f.size(); ++i) c[header[i]] = f[i];
    CostRow r;
    r.variant = c["variant"];
    for (const auto& h : header)
      if (h.rfind("axes.", 0) == 0 && !c[h].empty()) r.axes[h.substr(5)] = c[h];
    r.spirv_hash = c["spirv_hash"];
    r.scene = c["scene"];
    r.view = c["view"];
    r.backend = c["backend"];
    r.size = c["size"];
    r.threads = static_cast<int>(parse_double(c["threads"], "threads"));
    r.time_ms = {parse_double(c["time_ms.min"], "time_ms.min"), parse_double(c["time_ms.median"], "time_ms.median"),
                 parse_double(c["time_ms.p90"], "time_ms.p90"),
                 static_cast<int>(parse_double(c["time_ms.n"], "time_ms.n"))};
    if (c.count("time_ms.paired")) r.time_ms.paired = parse_double(c["time_ms.paired"], "time_ms.paired");
    r.rel_time = parse_double(c["rel_time"], "rel_time");
    if (c.count("rel_time_median")) r.rel_time_median = parse_double(c["rel_time_median"], "rel_time_median");
    if (!c["error.rmse"].empty()) {
      metrics::ErrorStats e;
      for (int i = 0; i < 6; ++i) {
        std::string col = std::string("error.") + kErrorFields[i];
        error_field(e, i) = parse_double(c[col], col);
      }
      r.error = e;
    }
    r.health.nan = static_cast<long>(parse_double(c["health.nan"], "health.nan"));
    r.health.inf = static_cast<long>(parse_double(c["health.inf"], "health.inf"));
    r.health.out_of_range = static_cast<long>(parse_double(c["health.out_of_range"], "health.out_of_range"));
    r.pareto = c["pareto"] == "true";
    r.predicted = c["predicted"] == "true";
    if (!c["flicker"].empty()) r.flicker = parse_double(c["flicker"], "flicker");
    const std::string& im = c["images"];
    for (std::size_t start = 0; !im.empty() && start <= im.size();) {
      std::size_t end = im.find(';', start);
      r.images.push_back(im.substr(start, end == std::string::npos ? std::string::npos : end - start));
      if (end == std::string::npos) break;
      start = end + 1;
    }
    r.static_cost = c["static"].empty() ? std::nullopt : static_cost_from_json(json::parse(c["static"]));
    t.rows.push_back(std::move(r));
  }
  return t;
}

// ---- Markdown ----

namespace {
std::string md_cell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out;
}
}  // namespace

std::string to_markdown(const CostTable& t) {
  std::vector<const CostRow*> rows;
  for (const auto& r : t.rows) rows.push_back(&r);
  std::stable_sort(rows.begin(), rows.end(), [](const CostRow* a, const CostRow* b) {
    double ta = a->time_ms.decision(), tb = b->time_ms.decision();
    return std::tie(a->scene, a->view, ta, a->variant, a->backend) < std::tie(b->scene, b->view, tb, b->variant, b->backend);
  });
  std::string out =
      "| scene | view | backend | variant | paired ms | min ms | median ms | rel | rmse | ssim | psnr | pareto |\n"
      "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|:---:|\n";
  for (const CostRow* r : rows) {
    std::string err = " - | - | - ";
    if (r->error)
      err = fmt::format(" {:.4f} | {:.4f} | {} ", r->error->rmse, r->error->ssim,
                        std::isfinite(r->error->psnr) ? fmt::format("{:.2f}", r->error->psnr) : "inf");
    std::string time = r->predicted ? fmt::format("~{:.3f} (predicted)", r->time_ms.min)
                                    : fmt::format("{:.3f}", r->time_ms.min);
    std::string paired = r->predicted ? std::string("-") : r->time_ms.paired > 0 ? fmt::format("{:.3f}", r->time_ms.paired) : "-";
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.2f} |{}| {} |\n", md_cell(r->scene), md_cell(r->view),
                       md_cell(r->backend), md_cell(r->variant), paired, time,
                       r->predicted ? std::string("-") : fmt::format("{:.3f}", r->time_ms.median), r->rel_time, err,
                       r->pareto ? "*" : "");
  }
  return out + pruned_summary(t);
}

std::string pruned_summary(const CostTable& t) {
  const json none = json::array();
  const json& pruned = t.meta.is_object() && t.meta.contains("pruned") ? t.meta.at("pruned") : none;
  std::string out;
  for (const auto& p : pruned) {
    std::string rules;
    const json counts = p.value("rules", json::object());
    for (const auto& [rule, n] : counts.items())
      rules += fmt::format("{}{} {}", rules.empty() ? "" : ", ", rule, n.dump());
    out += fmt::format("- {}: {} selected, {} kept, {} dropped{}\n", p.value("scene", ""), p.value("selected", 0),
                       p.value("kept", 0), p.value("dropped", 0), rules.empty() ? "" : " (" + rules + ")");
  }
  if (out.empty()) return out;
  return "\nPruned before compiling by each scene's profile (every dropped variant with its reason: cost_table.json "
         "meta.pruned; `--no-prune` measures them):\n\n" + out;
}

void write_table_files(const CostTable& table, const std::filesystem::path& dir) {
  write_json(table, dir / "cost_table.json");
  util::write_atomic(dir / "cost_table.csv", to_csv(table));
  util::write_atomic(dir / "cost_table.md", to_markdown(table));
}

// ---- Pareto ----

void mark_pareto(std::vector<CostRow>& rows) {
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<CostRow*>> groups;
  for (auto& r : rows) {
    r.pareto = false;
    if (r.error && !std::isnan(r.error->rmse)) groups[{r.scene, r.view, r.backend}].push_back(&r);
  }
  for (auto& [g, members] : groups) {
    std::sort(members.begin(), members.end(), [](const CostRow* a, const CostRow* b) {
      double ta = a->time_ms.decision(), tb = b->time_ms.decision();
      return std::tie(ta, a->error->rmse, a->variant) < std::tie(tb, b->error->rmse, b->variant);
    });
    // Sweep in time order: a row is dominated by an earlier one (time <= its time) with lower error, or
    // with equal error and strictly lower time. min_t is the lowest time reaching min_e (the first in order).
    double min_e = std::numeric_limits<double>::infinity(), min_t = 0;
    for (CostRow* r : members) {
      double e = r->error->rmse, t = r->time_ms.decision();
      bool dominated = min_e < e || (min_e == e && min_t < t);
      r->pareto = !dominated;
      if (e < min_e) {
        min_e = e;
        min_t = t;
      }
    }
  }
}

std::vector<CostRow> worst_view(const std::vector<CostRow>& rows) {
  std::map<std::tuple<std::string, std::string, std::string, std::string, int>, std::vector<const CostRow*>> groups;
  for (const auto& r : rows)
    if (r.error) groups[{r.scene, r.variant, r.backend, r.size, r.threads}].push_back(&r);
  std::vector<CostRow> out;
  for (const auto& [g, members] : groups) {
    std::vector<const CostRow*> sorted = members;
    std::sort(sorted.begin(), sorted.end(), [](const CostRow* a, const CostRow* b) { return a->view < b->view; });
    const CostRow* worst = sorted[0];
    CostRow agg = *worst;
    std::string views;
    for (const CostRow* r : sorted) {
      if (r->error->rmse > worst->error->rmse) worst = r;
      agg.time_ms.min = std::max(agg.time_ms.min, r->time_ms.min);
      agg.time_ms.median = std::max(agg.time_ms.median, r->time_ms.median);
      agg.time_ms.p90 = std::max(agg.time_ms.p90, r->time_ms.p90);
      agg.time_ms.n = std::min(agg.time_ms.n, r->time_ms.n);
      agg.time_ms.paired = std::max(agg.time_ms.paired, r->time_ms.paired);
      agg.rel_time = std::max(agg.rel_time, r->rel_time);
      agg.predicted = agg.predicted || r->predicted;
      agg.health.nan += r == sorted[0] ? 0 : r->health.nan;
      agg.health.inf += r == sorted[0] ? 0 : r->health.inf;
      agg.health.out_of_range += r == sorted[0] ? 0 : r->health.out_of_range;
      if (r->flicker) agg.flicker = std::max(agg.flicker.value_or(0.0), *r->flicker);
      views += (views.empty() ? "" : ",") + r->view;
    }
    agg.error = worst->error;
    agg.view = "worst(" + views + ")";
    agg.images.clear();
    out.push_back(std::move(agg));
  }
  // Front per (scene, backend): the aggregated rows' view names differ only by which views were present.
  std::map<std::pair<std::string, std::string>, std::vector<CostRow>> by;
  for (auto& r : out) by[{r.scene, r.backend}].push_back(r);
  out.clear();
  for (auto& [k, group] : by) {
    std::vector<std::string> views;
    for (auto& r : group) views.push_back(std::exchange(r.view, "worst"));
    mark_pareto(group);
    for (std::size_t i = 0; i < group.size(); ++i) {
      group[i].view = views[i];
      out.push_back(std::move(group[i]));
    }
  }
  return out;
}

}  // namespace aovar::table
