// The registered GL vendors, and the parsing every shader-db line shares.
#include <cctype>
#include <cmath>
#include <regex>
#include <sstream>

#include "gpu/gl/vendor.h"

namespace aovar::gpu {

// One line per vendor: gpu/gl/vendors/<name>.cpp.
const GlVendor& nouveau_vendor();
const GlVendor& freedreno_vendor();
const GlVendor& panfrost_vendor();
const GlVendor& intel_vendor();

const std::vector<const GlVendor*>& gl_vendors() {
  static const std::vector<const GlVendor*> all = {&nouveau_vendor(), &freedreno_vendor(), &panfrost_vendor(),
                                                   &intel_vendor()};
  return all;
}

const GlVendor* gl_vendor(const std::string& name) {
  for (const GlVendor* v : gl_vendors())
    if (v->name == name) return v;
  return nullptr;
}

std::map<std::string, double> counted_fields(const std::string& list) {
  static const std::regex count(R"(^\s*(-?[0-9]+(?:\.[0-9]+)?)\s+(.+?)\s*$)");
  static const std::regex pair(R"(^\s*([0-9]+):([0-9]+)\s+([A-Za-z_]+):([A-Za-z_]+)\s*$)");
  std::map<std::string, double> values;
  std::istringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    std::smatch m;
    if (std::regex_match(item, m, pair)) {
      values[m[3]] = std::stod(m[1]);
      values[m[4]] = std::stod(m[2]);
    } else if (std::regex_match(item, m, count)) {
      values[m[2]] = std::stod(m[1]);
    }
  }
  return values;
}

const std::string* last_line_with(const std::vector<std::string>& messages, const std::string& tag) {
  for (auto line = messages.rbegin(); line != messages.rend(); ++line)
    if (line->find(tag) != std::string::npos) return &*line;
  return nullptr;
}

double field(const std::map<std::string, double>& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? NAN : it->second;
}

double field_sum(const std::map<std::string, double>& values, const std::vector<std::string>& names) {
  double total = NAN;
  for (const std::string& n : names) {
    const double v = field(values, n);
    if (!std::isnan(v)) total = std::isnan(total) ? v : total + v;
  }
  return total;
}

ShaderStats line_stats(std::map<std::string, double> values, const std::string& line) {
  ShaderStats s;
  s.values = std::move(values);
  s.raw = line;
  s.instructions = field(s.values, "inst");
  return s;
}

std::optional<ShaderStats> tagged_line_stats(const std::vector<std::string>& messages, const std::string& tag) {
  const std::string* line = last_line_with(messages, tag);
  if (!line) return std::nullopt;
  return line_stats(counted_fields(line->substr(line->find(tag) + tag.size())), *line);
}

double instructions_issued(const ShaderStats& stats) { return stats.instructions; }

}  // namespace aovar::gpu
