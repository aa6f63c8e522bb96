#include "gpu/family_specs.h"

#include <algorithm>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace aovar::gpu {
extern const char* const kFamiliesJson;  // families_embedded.cpp, generated from src/gpu/families.json

namespace {

double positive(const nlohmann::json& e, const char* name, const std::string& family) {
  const double v = e.at(name).get<double>();
  if (!(v > 0)) throw std::runtime_error("gpu/families.json: " + family + "." + name + " must be positive");
  return v;
}

FamilySpec spec_from(const nlohmann::json& e) {
  FamilySpec s;
  s.family = e.at("family").get<std::string>();
  s.aliases = e.value("aliases", std::vector<std::string>{});
  s.product = e.at("product").get<std::string>();
  s.source = e.at("source").get<std::string>();
  if (s.product.empty() || s.source.empty())
    throw std::runtime_error("gpu/families.json: " + s.family + " needs a product and a source");
  s.cus = static_cast<int>(positive(e, "cus", s.family));
  s.simds_per_cu = static_cast<int>(positive(e, "simds_per_cu", s.family));
  s.wave_size = static_cast<int>(positive(e, "wave_size", s.family));
  s.clock_mhz = positive(e, "clock_mhz", s.family);
  s.tmus = positive(e, "tmus", s.family);
  s.bandwidth_gbs = positive(e, "bandwidth_gbs", s.family);
  return s;
}

std::vector<FamilySpec> parse_specs() {
  std::vector<FamilySpec> specs;
  try {
    const nlohmann::json file = nlohmann::json::parse(kFamiliesJson);  // kept: the loop iterates a member
    for (const auto& e : file.at("families")) specs.push_back(spec_from(e));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("gpu/families.json (embedded): ") + e.what());
  }
  return specs;
}

}  // namespace

const std::vector<FamilySpec>& family_specs() {
  static const std::vector<FamilySpec> specs = parse_specs();
  return specs;
}

const FamilySpec* family_spec(const std::string& family) {
  for (const FamilySpec& s : family_specs())
    if (s.family == family || std::find(s.aliases.begin(), s.aliases.end(), family) != s.aliases.end()) return &s;
  return nullptr;
}

}  // namespace aovar::gpu
