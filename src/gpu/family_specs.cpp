#include "gpu/family_specs.h"

#include <algorithm>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "gpu/gl/vendor.h"

namespace aovar::gpu {
extern const char* const kFamiliesJson;  // families_embedded.cpp, generated from src/gpu/families.json

namespace {

struct Data {
  std::vector<FamilySpec> families, reference;
  std::map<std::string, std::string> sources;
};

[[noreturn]] void bad(const std::string& what) { throw std::runtime_error("gpu/families.json: " + what); }

double positive(const nlohmann::json& e, const char* name, const std::string& family) {
  const double v = e.at(name).get<double>();
  if (!(v > 0)) bad(family + "." + name + " must be positive");
  return v;
}

CacheScope scope_from(const std::string& s, const std::string& where) {
  if (s == "cu") return CacheScope::cu;
  if (s == "shader_array") return CacheScope::shader_array;
  if (s == "chip") return CacheScope::chip;
  bad(where + ".scope is '" + s + "': use cu, shader_array or chip");
}

CacheLevelSpec level_from(const nlohmann::json& e, const std::string& family,
                          const std::map<std::string, std::string>& sources) {
  CacheLevelSpec c;
  c.name = e.at("name").get<std::string>();
  const std::string where = family + ".caches." + c.name;
  c.scope = scope_from(e.at("scope").get<std::string>(), where);
  c.size_bytes = static_cast<int64_t>(positive(e, "size_kb", where) * 1024);
  c.line_bytes = static_cast<int>(positive(e, "line_bytes", where));
  c.ways = static_cast<int>(positive(e, "ways", where));
  c.bytes_per_clock = positive(e, "bytes_per_clock", where);
  if (c.line_bytes < 4 || (c.line_bytes & (c.line_bytes - 1)) != 0) bad(where + ".line_bytes must be a power of two >= 4");
  if (c.size_bytes % (int64_t(c.line_bytes) * c.ways) != 0) bad(where + ": size_kb is not a whole number of sets");
  c.sources = e.at("sources").get<std::map<std::string, std::string>>();
  for (const char* figure : {"size_kb", "line_bytes", "ways", "bytes_per_clock"}) {
    const auto it = c.sources.find(figure);
    if (it == c.sources.end()) bad(where + " names no source for " + figure);
    if (!sources.count(it->second)) bad(where + "." + figure + " cites '" + it->second + "', not in 'sources'");
  }
  return c;
}

FamilySpec spec_from(const nlohmann::json& e, const std::map<std::string, std::string>& sources) {
  FamilySpec s;
  s.family = e.at("family").get<std::string>();
  s.aliases = e.value("aliases", std::vector<std::string>{});
  s.product = e.at("product").get<std::string>();
  s.source = e.at("source").get<std::string>();
  if (s.product.empty() || s.source.empty()) bad(s.family + " needs a product and a source");
  s.vendor = e.value("vendor", std::string("amd"));
  s.cus = static_cast<int>(positive(e, "cus", s.family));
  s.simds_per_cu = static_cast<int>(positive(e, "simds_per_cu", s.family));
  s.wave_size = static_cast<int>(positive(e, "wave_size", s.family));
  s.clock_mhz = positive(e, "clock_mhz", s.family);
  if (e.contains("shader_clock_mhz")) s.shader_clock_mhz = positive(e, "shader_clock_mhz", s.family);
  s.tmus = positive(e, "tmus", s.family);
  s.bandwidth_gbs = positive(e, "bandwidth_gbs", s.family);
  s.shader_engines = static_cast<int>(positive(e, "shader_engines", s.family));
  s.shader_arrays_per_engine = static_cast<int>(positive(e, "shader_arrays_per_engine", s.family));
  if (e.contains("alu_lanes")) s.alu_lanes = positive(e, "alu_lanes", s.family);
  s.validation = e.value("validation", std::string());
  if (s.cus < s.shader_arrays()) bad(s.family + " has fewer CUs than shader arrays");
  for (const auto& c : e.at("caches")) s.caches.push_back(level_from(c, s.family, sources));
  if (s.caches.empty()) bad(s.family + ".caches is empty");
  // The headline figures' citations (optional; "source-page" is the entry's own `source`).
  for (const auto& [figure, key] : e.value("sources", std::map<std::string, std::string>{}))
    if (key != "source-page" && !sources.count(key)) bad(s.family + ".sources." + figure + " cites '" + key + "', not in 'sources'");
  if (e.contains("compiler")) {
    s.compiler = CompilerRef{e.at("compiler").at("driver").get<std::string>(), e.at("compiler").at("chip").get<std::string>()};
    if (!gl_vendor(s.compiler->driver)) bad(s.family + ".compiler.driver '" + s.compiler->driver + "' is no registered GL vendor");
    if (s.compiler->chip.empty()) bad(s.family + ".compiler.chip is empty");
  }
  return s;
}

Data parse_data() {
  Data d;
  try {
    const nlohmann::json file = nlohmann::json::parse(kFamiliesJson);  // kept: the loops iterate members
    d.sources = file.at("sources").get<std::map<std::string, std::string>>();
    for (const auto& e : file.at("families")) d.families.push_back(spec_from(e, d.sources));
    for (const auto& e : file.at("reference_products")) d.reference.push_back(spec_from(e, d.sources));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("gpu/families.json (embedded): ") + e.what());
  }
  return d;
}

const Data& data() {
  static const Data d = parse_data();
  return d;
}

const FamilySpec* find_in(const std::vector<FamilySpec>& specs, const std::string& name) {
  for (const FamilySpec& s : specs)
    if (s.family == name || std::find(s.aliases.begin(), s.aliases.end(), name) != s.aliases.end()) return &s;
  return nullptr;
}

}  // namespace

const std::vector<FamilySpec>& family_specs() { return data().families; }
const std::vector<FamilySpec>& reference_products() { return data().reference; }
const std::map<std::string, std::string>& cache_sources() { return data().sources; }

const FamilySpec* family_spec(const std::string& family) { return find_in(family_specs(), family); }

std::vector<const FamilySpec*> gl_chips() {
  std::vector<const FamilySpec*> chips;
  for (const FamilySpec& s : reference_products())
    if (s.compiler) chips.push_back(&s);
  return chips;
}

const FamilySpec* gl_chip(const std::string& name) {
  const FamilySpec* s = find_in(reference_products(), name);
  return s && s->compiler ? s : nullptr;
}

const FamilySpec* estimate_spec(const std::string& name) {
  if (const FamilySpec* s = family_spec(name)) return s;
  const FamilySpec* chip = gl_chip(name);
  return chip && chip->alu_lanes > 0 ? chip : nullptr;
}

std::string validation_line(const std::string& name) {
  const FamilySpec* s = estimate_spec(name);
  if (!s) return name + ": no estimate (compiler statistics only)";
  const std::string what = name + " (" + s->product + ")";
  if (s->validation.empty()) return what + ": no validation (no paper measured this chip)";
  return what + ": validated against " + s->validation + " (bench/gpu_seeds)";
}

const FamilySpec* product_spec(const std::string& name) {
  const FamilySpec* s = family_spec(name);
  return s ? s : find_in(reference_products(), name);
}

}  // namespace aovar::gpu
