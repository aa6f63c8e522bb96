#include "gpu/stats.h"

#include <algorithm>
#include <cctype>
#include <vector>

namespace aovar::gpu {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// ACO's statistic names (Mesa 22.3 and 25.x spell these the same; others are kept in `values` only).
struct Field {
  const char* name;
  double ShaderStats::*field;
  Combine how;
};
constexpr Field kFields[] = {
    {"sgprs", &ShaderStats::sgprs, Combine::max},
    {"vgprs", &ShaderStats::vgprs, Combine::max},
    {"spilled sgprs", &ShaderStats::spill_sgprs, Combine::sum},
    {"spilled vgprs", &ShaderStats::spill_vgprs, Combine::sum},
    {"subgroups per simd", &ShaderStats::subgroups_per_simd, Combine::min},
    {"instructions", &ShaderStats::instructions, Combine::sum},
    {"copies", &ShaderStats::copies, Combine::sum},
    {"branches", &ShaderStats::branches, Combine::sum},
    {"vmem clause", &ShaderStats::vmem_clauses, Combine::sum},
    {"smem clause", &ShaderStats::smem_clauses, Combine::sum},
    {"latency", &ShaderStats::latency, Combine::sum},
    {"inverse throughput", &ShaderStats::inverse_throughput, Combine::sum},
    {"code size", &ShaderStats::code_size, Combine::sum},
    {"lds size", &ShaderStats::lds, Combine::max},
    {"scratch size", &ShaderStats::scratch, Combine::max},
};

double value_of(const std::map<std::string, double>& values, const char* name) {
  for (const auto& [key, value] : values)
    if (lower(key) == name) return value;
  return NAN;
}

double sum_of(double a, double b) { return std::isnan(a) ? b : std::isnan(b) ? a : a + b; }

// ACO's counts in the neutral terms: VALU + SALU is the arithmetic, VMEM the texture path (image samples
// and loads both), SMEM the scalar memory; occupancy is waves per SIMD, the cycle estimate ACO's latency.
void fill_neutral_from_aco(ShaderStats& s) {
  s.alu = sum_of(value_of(s.values, "valu"), value_of(s.values, "salu"));
  s.texture = value_of(s.values, "vmem");
  s.memory = value_of(s.values, "smem");
  s.registers = s.vgprs;
  s.occupancy = s.subgroups_per_simd;
  s.spills = sum_of(s.spill_vgprs, s.spill_sgprs);
  s.cycles = s.latency;
}

bool matches(const std::string& name, const Field& f) {
  const std::string key = lower(name);
  return key == f.name || key == std::string(f.name) + "s";  // "VMEM Clause" or "VMEM Clauses"
}

}  // namespace

ShaderStats ShaderStats::from_values(std::map<std::string, double> values) {
  ShaderStats s;
  for (const auto& [name, value] : values)
    for (const Field& f : kFields)
      if (matches(name, f)) s.*(f.field) = value;
  s.values = std::move(values);
  fill_neutral_from_aco(s);
  return s;
}

const std::vector<NeutralField>& neutral_fields() {
  static const std::vector<NeutralField> fields = {
      {"instructions", &ShaderStats::instructions, Combine::sum}, {"alu", &ShaderStats::alu, Combine::sum},
      {"texture", &ShaderStats::texture, Combine::sum},           {"memory", &ShaderStats::memory, Combine::sum},
      {"registers", &ShaderStats::registers, Combine::max},       {"occupancy", &ShaderStats::occupancy, Combine::min},
      {"spills", &ShaderStats::spills, Combine::sum},             {"cycles", &ShaderStats::cycles, Combine::sum},
      {"loops", &ShaderStats::loops, Combine::sum},
  };
  return fields;
}

// How a statistic of several passes adds up: counts and cycles sum (what a frame issues), registers and
// occupancy do not: the worst pass (the largest allocation, the fewest waves).
ShaderStats combine(const std::vector<const ShaderStats*>& passes) {
  std::map<std::string, double> values;
  for (const ShaderStats* p : passes)
    for (const auto& [name, value] : p->values) {
      if (lower(name).find("hash") != std::string::npos) continue;  // "Hash", "Driver pipeline hash": per pass only
      auto how = Combine::sum;
      for (const Field& f : kFields)
        if (matches(name, f)) how = f.how;
      auto [it, fresh] = values.emplace(name, value);
      if (fresh) continue;
      it->second = how == Combine::sum ? it->second + value
                   : how == Combine::max ? std::max(it->second, value) : std::min(it->second, value);
    }
  ShaderStats total = ShaderStats::from_values(std::move(values));
  // The neutral fields by their own rule: for a GL compiler's statistics they do not come from ACO's names.
  for (const NeutralField& f : neutral_fields()) {
    double v = NAN;
    for (const ShaderStats* p : passes) {
      const double x = p->*(f.field);
      if (std::isnan(x)) continue;
      v = std::isnan(v) ? x : f.how == Combine::sum ? v + x : f.how == Combine::max ? std::max(v, x) : std::min(v, x);
    }
    total.*(f.field) = v;
  }
  return total;
}

nlohmann::json neutral_json(const ShaderStats& s) {
  nlohmann::json j = nlohmann::json::object();
  for (const NeutralField& f : neutral_fields())
    if (!std::isnan(s.*(f.field))) j[f.name] = s.*(f.field);
  return j;
}

nlohmann::json to_json(const ShaderStats& s) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, value] : s.values) j[name] = value;
  return j;
}

ShaderStats stats_from_json(const nlohmann::json& j) {
  std::map<std::string, double> values;
  for (const auto& [name, value] : j.items()) values[name] = value.get<double>();
  return ShaderStats::from_values(std::move(values));
}

}  // namespace aovar::gpu
