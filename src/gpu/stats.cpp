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
  enum { sum, max, min } how;
};
constexpr Field kFields[] = {
    {"sgprs", &ShaderStats::sgprs, Field::max},
    {"vgprs", &ShaderStats::vgprs, Field::max},
    {"spilled sgprs", &ShaderStats::spill_sgprs, Field::sum},
    {"spilled vgprs", &ShaderStats::spill_vgprs, Field::sum},
    {"subgroups per simd", &ShaderStats::subgroups_per_simd, Field::min},
    {"instructions", &ShaderStats::instructions, Field::sum},
    {"copies", &ShaderStats::copies, Field::sum},
    {"branches", &ShaderStats::branches, Field::sum},
    {"vmem clause", &ShaderStats::vmem_clauses, Field::sum},
    {"smem clause", &ShaderStats::smem_clauses, Field::sum},
    {"latency", &ShaderStats::latency, Field::sum},
    {"inverse throughput", &ShaderStats::inverse_throughput, Field::sum},
    {"code size", &ShaderStats::code_size, Field::sum},
    {"lds size", &ShaderStats::lds, Field::max},
    {"scratch size", &ShaderStats::scratch, Field::max},
};

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
  return s;
}

// How a statistic of several passes adds up: counts and cycles sum (what a frame issues), registers and
// occupancy do not: the worst pass (the largest allocation, the fewest waves).
ShaderStats combine(const std::vector<const ShaderStats*>& passes) {
  std::map<std::string, double> values;
  for (const ShaderStats* p : passes)
    for (const auto& [name, value] : p->values) {
      if (lower(name).find("hash") != std::string::npos) continue;  // "Hash", "Driver pipeline hash": per pass only
      auto how = Field::sum;
      for (const Field& f : kFields)
        if (matches(name, f)) how = f.how;
      auto [it, fresh] = values.emplace(name, value);
      if (fresh) continue;
      it->second = how == Field::sum ? it->second + value
                   : how == Field::max ? std::max(it->second, value) : std::min(it->second, value);
    }
  return ShaderStats::from_values(std::move(values));
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
