// Reading cost_table.json (table.h: read_table, table_from_json, row_from_json). simdjson's On-Demand parser
// (Langdale & Lemire, 2019, for the structural index; Keiser & Lemire, 2024, for On-Demand) walks the file
// once and each row's fields go straight into its CostRow: no document of the table and no per-row JSON
// objects, which were most of the time and memory of `select` and `report` on large tables (bench/HISTORY.md,
// "bench/big_inputs"). "static" and "error.breakdown" are read by the member lists their writers use
// (static_cost_fields.h, detail.h); "gpu" and "meta" go through their nlohmann readers. Values of fields aovar
// does not know are skipped, not checked.
#include <simdjson.h>
#include <sys/mman.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <span>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <unordered_map>

#include "table/detail.h"
#include "table/ondemand_json.h"
#include "table/static_cost_fields.h"
#include "table/table.h"
#include "table/validate.h"
#include "util/fs.h"
#include "util/schema.h"
#include "util/text.h"

namespace aovar::table {
namespace {
using namespace ondemand_json;  // od::, the typed getters, each_field, to_nlohmann

// The members `fields` names from the object `v` into `out`; other keys go to `other`. Returns the keys seen.
template <class Struct, class Member, std::size_t N, class Other>
std::size_t read_fields(od::value v, std::string_view path, Struct& out,
                        const static_fields::Field<Struct, Member> (&fields)[N], Other&& other) {
  std::uint32_t seen = 0;
  std::size_t keys = 0;
  each_field(v, path, [&](std::string_view key, od::value x) {
    ++keys;
    for (std::size_t i = 0; i < N; ++i)
      if (key == fields[i].name) {
        if constexpr (std::is_same_v<Member, int>) out.*fields[i].member = int_of(x, key);
        else out.*fields[i].member = number_of(x, key);
        seen |= 1u << i;
        return;
      }
    other(key, x);
  });
  for (std::size_t i = 0; i < N; ++i)
    if (fields[i].required && !(seen & (1u << i))) missing(path, fields[i].name);
  return keys;
}
constexpr auto kNoOther = [](std::string_view, od::value) {};

ProgramCounts counts_of(od::value v, std::string_view path) {
  ProgramCounts c;
  bool fetches = false;
  read_fields(v, path, c, static_fields::kCounts, [&](std::string_view key, od::value x) {
    if (key == "fetches") {
      read_fields(x, "fetches", c.fetches, static_fields::kFetches, kNoOther);
      fetches = true;
    }
    if (key == "loops") read_fields(x, "loops", c, static_fields::kLoops, kNoOther);
  });
  if (!fetches) missing(path, "fetches");
  return c;
}

// "static" (table/static_cost.h): null or {} when the variant was not analysed.
std::optional<StaticCost> static_of(od::value v) {
  if (is_null(v)) return std::nullopt;
  StaticCost s;
  bool ao = false, passes = false;
  const std::size_t keys = read_fields(v, "static", s, static_fields::kCost, [&](std::string_view key, od::value x) {
    if (key == "ao") {
      s.ao = counts_of(x, "static.ao");
      ao = true;
    }
    if (key == "passes") {
      s.passes = counts_of(x, "static.passes");
      passes = true;
    }
    if (key != "weighted") return;
    bool weighted_ao = false, others = false;
    each_field(x, "static.weighted", [&](std::string_view part, od::value y) {
      if (part == "ao") {
        read_fields(y, "static.weighted.ao", s.weighted_ao, static_fields::kClasses, kNoOther);
        weighted_ao = true;
      }
      if (part == "others") {
        read_fields(y, "static.weighted.others", s.weighted_others, static_fields::kClasses, kNoOther);
        others = true;
      }
    });
    if (!weighted_ao) missing("static.weighted", "ao");
    if (!others) missing("static.weighted", "others");
  });
  if (keys == 0) return std::nullopt;
  if (!ao) missing("static", "ao");
  if (!passes) missing("static", "passes");
  return s;
}

// error.breakdown (metrics/breakdown.h): every value is there, NaN written as null.
metrics::ErrorPart part_of(od::value v, std::string_view name) {
  metrics::ErrorPart p;
  std::uint32_t seen = 0;
  each_field(v, name, [&](std::string_view key, od::value x) {
    for (std::size_t i = 0; i < std::size(detail::kPartValues); ++i)
      if (key == detail::kPartValues[i].name) {
        p.*detail::kPartValues[i].value = nan_or_number(x, key);
        seen |= 1u << i;
      }
  });
  for (std::size_t i = 0; i < std::size(detail::kPartValues); ++i)
    if (!(seen & (1u << i))) missing(fmt::format("error.breakdown.{}", name), detail::kPartValues[i].name);
  return p;
}

metrics::ErrorBreakdown breakdown_of(od::value v) {
  metrics::ErrorBreakdown b;
  constexpr std::size_t kParts = std::size(detail::kBreakdownParts);
  std::uint32_t seen = 0;  // the parts by bit, then edge_band_px and split_depth
  each_field(v, "error.breakdown", [&](std::string_view key, od::value x) {
    for (std::size_t i = 0; i < kParts; ++i)
      if (key == detail::kBreakdownParts[i].name) {
        b.*detail::kBreakdownParts[i].part = part_of(x, key);
        seen |= 1u << i;
      }
    if (key == "edge_band_px") {
      b.edge_band_px = nan_or_number(x, key);
      seen |= 1u << kParts;
    }
    if (key == "split_depth") {
      b.split_depth = nan_or_number(x, key);
      seen |= 2u << kParts;
    }
  });
  for (std::size_t i = 0; i < kParts; ++i)
    if (!(seen & (1u << i))) missing("error.breakdown", detail::kBreakdownParts[i].name);
  if (!(seen & (1u << kParts))) missing("error.breakdown", "edge_band_px");
  if (!(seen & (2u << kParts))) missing("error.breakdown", "split_depth");
  return b;
}

Rounds rounds_of(od::value v) {
  Rounds r;
  Required required;
  each_field(v, "rounds", [&](std::string_view key, od::value x) {
    if (key == "scale") {
      r.scale = text_of(x, "rounds.scale");
      required.seen |= 1;
    }
    if (key == "id") {
      r.id = text_of(x, "rounds.id");
      required.seen |= 2;
    }
    if (key == "ratios") {
      r.ratios = numbers_of(x, "rounds.ratios");
      required.seen |= 4;
    }
  });
  constexpr const char* kNames[] = {"scale", "id", "ratios"};
  required.check(kNames, "rounds");
  detail::check_ratios(r.ratios);
  return r;
}

// A TimeStats object's fields, in the order of their required bits, and what each is called in messages.
constexpr const char* kStatsKeys[] = {"min", "median", "p90", "n"};
struct StatsNames {
  const char* object;
  const char* fields[4];  // kStatsKeys, prefixed: "time_ms.min", ...
  std::size_t required;   // how many of kStatsKeys (from the first) it must have
  bool paired;            // it has paired and paired_ci
};
// time_ms: min alone is required (tables written before the others). gbuffer_ms: all four, as written.
constexpr StatsNames kTimeNames{"time_ms", {"time_ms.min", "time_ms.median", "time_ms.p90", "time_ms.n"}, 1, true};
constexpr StatsNames kGbufferNames{
    "gbuffer_ms", {"gbuffer_ms.min", "gbuffer_ms.median", "gbuffer_ms.p90", "gbuffer_ms.n"}, 4, false};

util::TimeStats stats_of(od::value v, const StatsNames& names) {
  util::TimeStats t;
  double* const numbers[] = {&t.min, &t.median, &t.p90};
  Required required;
  each_field(v, names.object, [&](std::string_view key, od::value x) {
    const auto i = static_cast<std::size_t>(std::find(std::begin(kStatsKeys), std::end(kStatsKeys), key) - kStatsKeys);
    if (i < 3) *numbers[i] = number_of(x, names.fields[i]);
    if (i == 3) t.n = int_of(x, names.fields[3]);
    if (i < 4) required.seen |= 1u << i;
    if (names.paired && key == "paired") t.paired = number_of(x, "time_ms.paired");
    if (names.paired && key == "paired_ci") t.paired_ci = interval_of(x, "time_ms.paired_ci");
  });
  required.check(std::span(kStatsKeys, names.required), names.object);
  return t;
}

// The error against the reference: its six fields (null: not computed, read as +inf) and the breakdown.
metrics::ErrorStats error_of(od::value v) {
  metrics::ErrorStats e;
  Required required;
  each_field(v, "error", [&](std::string_view key, od::value x) {
    const auto* field = std::find(std::begin(detail::kErrorFields), std::end(detail::kErrorFields), key);
    if (field != std::end(detail::kErrorFields)) {
      const int i = static_cast<int>(field - std::begin(detail::kErrorFields));
      detail::error_field(e, i) = is_null(x) ? std::numeric_limits<double>::infinity() : number_of(x, key);
      required.seen |= 1u << i;
    } else if (key == "breakdown" && !is_null(x)) {  // tables written before it have none
      e.breakdown = breakdown_of(x);
    }
  });
  required.check(detail::kErrorFields, "error");
  return e;
}

image::Health health_of(od::value v) {
  image::Health h;
  each_field(v, "health", [&](std::string_view key, od::value x) {
    if (key == "nan") h.nan = whole_of(x, "health.nan");
    if (key == "inf") h.inf = whole_of(x, "health.inf");
    if (key == "out_of_range") h.out_of_range = whole_of(x, "health.out_of_range");
  });
  return h;
}

std::vector<std::string> texts_of(od::value v, std::string_view name) {
  std::vector<std::string> out;
  for (auto e : array_of(v, name)) out.push_back(text_of(e.value(), name));
  return out;
}

// One field of a row by its key; the row's required fields set their bit.
using FieldReader = void (*)(CostRow&, od::value, Required&);
const std::unordered_map<std::string_view, FieldReader>& field_readers() {
  static const std::unordered_map<std::string_view, FieldReader> readers = {
      {"variant", [](CostRow& r, od::value v, Required& q) {
        r.variant = text_of(v, "variant");
        q.seen |= 1;
      }},
      {"axes",
       [](CostRow& r, od::value v, Required& q) {
         r.axes.clear();
         each_field(v, "axes", [&](std::string_view name, od::value x) {
           std::string_view s;  // a value that is not a string: its JSON text
           r.axes[std::string(name)] = x.get_string().get(s) ? to_nlohmann(x).dump() : std::string(s);
         });
         q.seen |= 2;
       }},
      {"scene", [](CostRow& r, od::value v, Required& q) {
        r.scene = text_of(v, "scene");
        q.seen |= 4;
      }},
      {"view", [](CostRow& r, od::value v, Required& q) {
        r.view = text_of(v, "view");
        q.seen |= 8;
      }},
      {"backend", [](CostRow& r, od::value v, Required& q) {
        r.backend = text_of(v, "backend");
        q.seen |= 16;
      }},
      {"time_ms", [](CostRow& r, od::value v, Required& q) {
        r.time_ms = stats_of(v, kTimeNames);
        q.seen |= 32;
      }},
      {"gbuffer_ms",
       [](CostRow& r, od::value v, Required&) {
         r.gbuffer_ms = is_null(v) ? std::nullopt : std::optional(stats_of(v, kGbufferNames));
       }},
      {"spirv_hash", [](CostRow& r, od::value v, Required&) { r.spirv_hash = text_of(v, "spirv_hash"); }},
      {"device", [](CostRow& r, od::value v, Required&) { r.device = text_of(v, "device"); }},
      {"driver", [](CostRow& r, od::value v, Required&) { r.driver = text_of(v, "driver"); }},
      {"size", [](CostRow& r, od::value v, Required&) { r.size = text_of(v, "size"); }},
      {"threads", [](CostRow& r, od::value v, Required&) { r.threads = int_of(v, "threads"); }},
      {"static", [](CostRow& r, od::value v, Required&) { r.static_cost = static_of(v); }},
      {"gpu", [](CostRow& r, od::value v, Required&) { r.gpu = gpu_costs_from_json(to_nlohmann(v)); }},
      {"rel_time", [](CostRow& r, od::value v, Required&) { r.rel_time = number_of(v, "rel_time"); }},
      {"rel_time_median", [](CostRow& r, od::value v, Required&) { r.rel_time_median = number_of(v, "rel_time_median"); }},
      {"rel_time_ci", [](CostRow& r, od::value v, Required&) { r.rel_time_ci = interval_of(v, "rel_time_ci"); }},
      {"rounds", [](CostRow& r, od::value v, Required&) { r.rounds = is_null(v) ? Rounds{} : rounds_of(v); }},
      {"same_code_as", [](CostRow& r, od::value v, Required&) { r.same_code_as = text_of(v, "same_code_as"); }},
      {"error",
       [](CostRow& r, od::value v, Required&) {
         r.error = is_null(v) ? std::nullopt : std::optional(error_of(v));
       }},
      {"health", [](CostRow& r, od::value v, Required&) { r.health = health_of(v); }},
      {"pareto", [](CostRow& r, od::value v, Required&) { r.pareto = bool_of(v, "pareto"); }},
      {"predicted", [](CostRow& r, od::value v, Required&) { r.predicted = bool_of(v, "predicted"); }},
      {"flicker",
       [](CostRow& r, od::value v, Required&) {
         r.flicker = is_null(v) ? std::nullopt : std::optional(number_of(v, "flicker"));
       }},
      {"images", [](CostRow& r, od::value v, Required&) { r.images = texts_of(v, "images"); }},
  };
  return readers;
}

// A row's fields in file order (a field given twice: the last counts, as in any JSON reader that keeps one).
// Throws "row 'variant': field 'name': what is wrong" (the variant when it came before the field).
CostRow read_row(od::object o) {
  CostRow r;
  Required required;
  std::string field;
  try {
    for (auto f : o) {
      field = key_of(f);
      const auto reader = field_readers().find(field);
      if (reader != field_readers().end()) reader->second(r, f.value().value(), required);
    }
    field.clear();
    constexpr const char* kNames[] = {"variant", "axes", "scene", "view", "backend", "time_ms"};  // bits 1 to 32
    required.check(kNames, "");
  } catch (const simdjson::simdjson_error&) {
    throw;  // not well formed: said as such, with the line (with_document)
  } catch (const std::exception& e) {
    const std::string row = r.variant.empty() ? "" : "row '" + r.variant + "': ";
    throw std::runtime_error(field.empty() ? row + "field " + e.what() : row + "field '" + field + "': " + e.what());
  }
  return r;
}

// "meta" as read: an object (absent: an empty one).
SweepMeta checked_meta(const json& meta) {
  if (!meta.is_object())
    throw std::runtime_error(fmt::format("\"meta\" is {}, not an object (write {{}} when there is nothing in it)",
                                         meta.type_name()));
  return sweep_meta_from_json(meta);
}

// The text being parsed, and the line a message points at. With `release`, the pages wholly before the row
// being read go back to the system as the rows are read (madvise MADV_DONTNEED, once every 64 MiB): On-Demand
// reads forward only, and a 1,000,000-row table is 1.7 GB of text. Their newlines are counted first.
class Text {
 public:
  Text(const std::string& text, bool release) : text_(text), kept_(text.data()), release_(release) {}
  const std::string& str() const { return text_; }

  void release_before(const char* at) {
    constexpr std::ptrdiff_t kStep = std::ptrdiff_t{64} << 20;
    if (!release_ || at - kept_ < kStep) return;
    static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    const auto from = (reinterpret_cast<std::uintptr_t>(kept_) + page - 1) / page * page;
    const auto to = reinterpret_cast<std::uintptr_t>(at) / page * page;
    if (to <= from) return;
    lines_before_ += static_cast<std::size_t>(std::count(kept_, reinterpret_cast<const char*>(to), '\n'));
    ::madvise(reinterpret_cast<void*>(from), to - from, MADV_DONTNEED);
    kept_ = reinterpret_cast<const char*>(to);
  }

  // " (line N)" for where the document stands, or nothing when that is unknown.
  std::string where(od::document& doc) const {
    const char* at = nullptr;
    if (doc.current_location().get(at) || at < kept_ || at > text_.data() + text_.size()) return "";
    return fmt::format(" (line {})", 1 + lines_before_ + static_cast<std::size_t>(std::count(kept_, at, '\n')));
  }

 private:
  const std::string& text_;
  const char* kept_;              // the bytes before it are released
  std::size_t lines_before_ = 0;  // newlines before kept_
  bool release_;
};

// The table's meta and rows, not yet validated. `file` names it for the schema message (empty: not a file).
// "schema_version" comes after "rows" (keys are sorted) and is checked first: a newer aovar's table must be
// refused for its version, not for a row this one cannot read.
CostTable read_document(od::document& doc, Text& text, const std::filesystem::path& file) {
  if (doc.type().value() != od::json_type::object) throw std::runtime_error("not a cost table (no \"rows\" array)");
  if (!file.empty()) {
    od::value version;
    const simdjson::error_code found = doc.find_field_unordered("schema_version").get(version);
    if (found == simdjson::SUCCESS) util::check_schema_version(to_nlohmann(version), file);
    else if (found != simdjson::NO_SUCH_FIELD) throw simdjson::simdjson_error(found);  // the document is dead
  }
  doc.rewind();
  CostTable t;
  bool has_rows = false;
  for (auto top : doc.get_object()) {
    const std::string_view key = key_of(top);
    od::value v = top.value().value();
    if (key == "meta") t.meta = checked_meta(to_nlohmann(v));
    if (key != "rows") continue;
    od::array rows;
    if (v.get_array().get(rows)) throw std::runtime_error("not a cost table (no \"rows\" array)");
    has_rows = true;
    t.rows.clear();
    t.rows.reserve(rows.count_elements().value());  // the rows are most of the memory: no regrowth
    for (auto element : rows) {
      od::value row = element.value();
      const std::size_t index = t.rows.size();
      if (const char* at = nullptr; index % 4096 == 0 && !doc.current_location().get(at)) text.release_before(at);
      od::object o;
      if (row.get_object().get(o))
        throw std::runtime_error(fmt::format("row {}{} is {}, not an object", index, text.where(doc), type_name(row)));
      try {
        t.rows.push_back(read_row(o));
      } catch (const simdjson::simdjson_error&) {
        throw;
      } catch (const std::exception& e) {
        throw std::runtime_error(fmt::format("row {}{}: {}", index, text.where(doc), e.what()));
      }
    }
  }
  if (!has_rows) throw std::runtime_error("not a cost table (no \"rows\" array)");
  if (const char* rest = nullptr; !doc.current_location().get(rest))  // OUT_OF_BOUNDS: nothing is left
    throw std::runtime_error(fmt::format("text after the table's closing brace{}", text.where(doc)));
  return t;
}

// Parses the text (its capacity holds SIMDJSON_PADDING past the end) and hands the document to `use`;
// JSON that is not well formed fails in one line with simdjson's word for it and the line.
template <class Use>
auto with_document(Text& text, Use&& use) {
  od::parser parser;
  od::document doc;
  bool started = false;  // a document that never started has no position
  try {
    doc = parser.iterate(simdjson::padded_string_view(text.str().data(), text.str().size(), text.str().capacity()));
    started = true;
    return use(doc);
  } catch (const simdjson::simdjson_error& e) {
    throw std::runtime_error(fmt::format("not valid JSON{}: {} (fix the file or write it again)",
                                         started ? text.where(doc) : "", e.what()));
  }
}

std::string padded_text(const json& j) {
  std::string text = j.dump();
  text.reserve(text.size() + simdjson::SIMDJSON_PADDING);
  return text;
}

}  // namespace

CostRow row_from_json(const json& j) {
  const std::string padded = padded_text(j);
  Text text(padded, false);
  return with_document(text, [](od::document& doc) {
    od::object o;
    if (doc.get_object().get(o)) throw std::runtime_error("a row is not an object");
    return read_row(o);
  });
}

CostTable table_from_json(const json& j) {
  const std::string padded = padded_text(j);
  Text text(padded, false);
  CostTable t = with_document(text, [&](od::document& doc) { return read_document(doc, text, {}); });
  validate_rows(t.rows);
  return t;
}

CostTable read_table(const std::filesystem::path& path) {
  try {
    CostTable t;
    {  // the text and the parser's index are freed before the rows are validated
      auto content = util::read_file(path, util::kMaxReadBytes, simdjson::SIMDJSON_PADDING);
      if (!content) throw std::runtime_error("cannot read the cost table");
      Text text(*content, true);
      t = with_document(text, [&](od::document& doc) { return read_document(doc, text, path); });
    }
    validate_rows(t.rows);
    return t;
  } catch (const util::NewerSchema&) {
    throw;  // already names the file
  } catch (const util::ReadError&) {
    throw;  // already names the file
  } catch (const std::exception& e) {
    // One line whatever the file holds: a row or GPU name with a newline is quoted in these messages.
    throw std::runtime_error(util::display_path(path) + ": " + util::one_line(e.what()));
  }
}

}  // namespace aovar::table
