// The cost table as CSV (RFC 4180): one row per line, columns flattened.
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "table/detail.h"
#include "table/table.h"
#include "util/parse_number.h"

namespace aovar::table {
namespace {
using json = nlohmann::json;
using detail::error_field;
using detail::kErrorFields;

std::string text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{}", v);
}

double parse_double(const std::string& s, const std::string& column) {
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  const auto v = util::whole_double(s);
  if (!v) throw std::runtime_error("column '" + column + "': not a number: '" + s + "'");
  return *v;
}

}  // namespace

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
    "spirv_hash", "scene", "view", "backend", "device", "driver", "size", "threads", "time_ms.min", "time_ms.median", "time_ms.p90",
    "time_ms.n", "time_ms.paired", "time_ms.paired_lo", "time_ms.paired_hi", "gbuffer_ms.min", "gbuffer_ms.median",
    "gbuffer_ms.p90", "gbuffer_ms.n", "own_ms", "rel_time", "rel_time_median", "rel_time_lo",
    "rel_time_hi", "same_code_as", "error.rmse", "error.mae", "error.psnr", "error.ssim", "error.bias", "error.max",
    "health.nan", "health.inf", "health.out_of_range", "pareto", "predicted", "flicker", "images", "static", "gpu",
    "rounds", "error.breakdown", "err_edge_share", "err_far_share", "err_light_share"};
// Readable per-family columns after the fixed ones (the "gpu" column's JSON is what from_csv reads back).
// vgprs and waves are RADV's; instructions (every pass's, summed), registers (the most) and occupancy (the
// least) are the vendor-neutral ones every chip's compiler fills (schema_version 2).
const std::vector<std::string> kGpuColumns = {"est_ms", "bound", "vgprs", "waves", "instructions", "registers", "occupancy"};

// gbuffer_ms's four cells (read back) and own_ms, the variant's own part of the decision time (time_split,
// for a spreadsheet; not read back); all empty when the row has no measured split.
void gbuffer_cells(const CostRow& r, std::vector<std::string>& cells) {
  if (!r.gbuffer_ms) {
    cells.insert(cells.end(), 5, std::string());
    return;
  }
  const util::TimeStats& g = *r.gbuffer_ms;
  const std::optional<TimeSplit> split = time_split(r);
  cells.insert(cells.end(),
               {text(g.min), text(g.median), text(g.p90), std::to_string(g.n), split ? text(split->own) : ""});
}

// gbuffer_ms from its cells: empty or absent (a CSV written before it) when unknown.
std::optional<util::TimeStats> gbuffer_from(std::map<std::string, std::string>& c) {
  if (c["gbuffer_ms.min"].empty()) return std::nullopt;
  return util::TimeStats{parse_double(c["gbuffer_ms.min"], "gbuffer_ms.min"),
                         parse_double(c["gbuffer_ms.median"], "gbuffer_ms.median"),
                         parse_double(c["gbuffer_ms.p90"], "gbuffer_ms.p90"),
                         static_cast<int>(parse_double(c["gbuffer_ms.n"], "gbuffer_ms.n"))};
}
}  // namespace

std::string to_csv(const CostTable& t) {
  std::set<std::string> axis_names;
  for (const auto& r : t.rows)
    for (const auto& [k, v] : r.axes) axis_names.insert(k);
  std::vector<std::string> header = kFixedHead;
  for (const auto& a : axis_names) header.push_back("axes." + a);
  header.insert(header.end(), kFixedTail.begin(), kFixedTail.end());
  std::set<std::string> families;
  for (const auto& r : t.rows)
    for (const auto& [f, c] : r.gpu) families.insert(f);
  for (const auto& f : families)
    for (const auto& c : kGpuColumns) header.push_back("gpu." + f + "." + c);
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
    auto bound = [](double v) { return std::isnan(v) ? std::string() : text(v); };  // unknown interval: empty
    auto e = [&](int i) {
      if (!r.error) return std::string();
      metrics::ErrorStats copy = *r.error;
      return text(error_field(copy, i));
    };
    std::vector<std::string> tail = {r.spirv_hash, r.scene, r.view, r.backend, r.device, r.driver, r.size, std::to_string(r.threads),
                                     text(r.time_ms.min), text(r.time_ms.median), text(r.time_ms.p90),
                                     std::to_string(r.time_ms.n), text(r.time_ms.paired), bound(r.time_ms.paired_ci.lo),
                                     bound(r.time_ms.paired_ci.hi)};
    gbuffer_cells(r, tail);
    tail.insert(tail.end(), {text(r.rel_time), text(r.rel_time_median), bound(r.rel_time_ci.lo), bound(r.rel_time_ci.hi),
                             r.same_code_as, e(0), e(1), e(2), e(3), e(4), e(5), std::to_string(r.health.nan),
                             std::to_string(r.health.inf), std::to_string(r.health.out_of_range),
                             r.pareto ? "true" : "false", r.predicted ? "true" : "false",
                             r.flicker ? text(*r.flicker) : "", images,
                             r.static_cost ? to_json(r.static_cost).dump() : std::string("{}"),
                             r.gpu.empty() ? std::string("{}") : to_json(r.gpu).dump(),
                             r.rounds.ratios.empty() ? std::string() : to_json(r.rounds).dump()});
    // The breakdown: its JSON (what from_csv reads back), then the three shares a spreadsheet sorts by.
    const metrics::ErrorBreakdown* b = r.error && r.error->breakdown ? &*r.error->breakdown : nullptr;
    auto share = [&](const metrics::ErrorPart& p) { return std::isnan(p.error_share) ? std::string() : text(p.error_share); };
    if (b)
      tail.insert(tail.end(), {to_json(*b).dump(), share(b->edge), share(b->far), share(b->light)});
    else
      tail.insert(tail.end(), 4, std::string());
    f.insert(f.end(), tail.begin(), tail.end());
    for (const auto& family : families) {
      auto it = r.gpu.find(family);
      if (it == r.gpu.end()) {
        f.insert(f.end(), kGpuColumns.size(), "");
        continue;
      }
      const GpuCost& g = it->second;
      const GpuPassCost* slowest = g.slowest();
      auto number = [](double v) { return std::isnan(v) ? std::string() : text(v); };
      f.insert(f.end(), {number(g.est_ms), slowest ? slowest->pass + ":" + slowest->bound : "", number(g.max_vgprs()),
                         number(g.min_waves()), number(g.over_passes(&GpuPassCost::instructions, GpuCost::Combine::sum)),
                         number(g.over_passes(&GpuPassCost::registers, GpuCost::Combine::max)),
                         number(g.over_passes(&GpuPassCost::occupancy, GpuCost::Combine::min))});
    }
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
    r.device = c["device"];
    r.driver = c["driver"];
    r.size = c["size"];
    r.threads = static_cast<int>(parse_double(c["threads"], "threads"));
    r.time_ms = {parse_double(c["time_ms.min"], "time_ms.min"), parse_double(c["time_ms.median"], "time_ms.median"),
                 parse_double(c["time_ms.p90"], "time_ms.p90"),
                 static_cast<int>(parse_double(c["time_ms.n"], "time_ms.n"))};
    if (c.count("time_ms.paired")) r.time_ms.paired = parse_double(c["time_ms.paired"], "time_ms.paired");
    r.gbuffer_ms = gbuffer_from(c);
    r.rel_time = parse_double(c["rel_time"], "rel_time");
    if (c.count("rel_time_median")) r.rel_time_median = parse_double(c["rel_time_median"], "rel_time_median");
    auto interval = [&](const std::string& lo, const std::string& hi) {
      if (c[lo].empty() || c[hi].empty()) return util::Interval{};
      return util::Interval{parse_double(c[lo], lo), parse_double(c[hi], hi)};
    };
    r.time_ms.paired_ci = interval("time_ms.paired_lo", "time_ms.paired_hi");
    r.rel_time_ci = interval("rel_time_lo", "rel_time_hi");
    r.same_code_as = c["same_code_as"];
    if (!c["rounds"].empty()) r.rounds = rounds_from_json(json::parse(c["rounds"]));
    if (!c["error.rmse"].empty()) {
      metrics::ErrorStats e;
      for (int i = 0; i < 6; ++i) {
        std::string col = std::string("error.") + kErrorFields[i];
        error_field(e, i) = parse_double(c[col], col);
      }
      if (!c["error.breakdown"].empty()) e.breakdown = breakdown_from_json(json::parse(c["error.breakdown"]));
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
    if (!c["gpu"].empty()) r.gpu = gpu_costs_from_json(json::parse(c["gpu"]));
    t.rows.push_back(std::move(r));
  }
  return t;
}

}  // namespace aovar::table
