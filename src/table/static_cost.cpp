#include "table/static_cost.h"

#include <stdexcept>

#include "table/static_cost_fields.h"

namespace aovar::table {
namespace {
using json = nlohmann::json;

json counts_json(const ProgramCounts& c) {
  json out = json::object(), fetches = json::object(), loops = json::object();
  for (const auto& f : static_fields::kFetches) fetches[f.name] = c.fetches.*f.member;
  for (const auto& f : static_fields::kCounts) out[f.name] = c.*f.member;
  for (const auto& f : static_fields::kLoops) loops[f.name] = c.*f.member;
  out["fetches"] = std::move(fetches);
  out["loops"] = std::move(loops);
  return out;
}

json classes_json(const ClassCounts& k) {
  json out = json::object();
  for (const auto& f : static_fields::kClasses) out[f.name] = k.*f.member;
  return out;
}

ProgramCounts counts_from(const json& j) {
  ProgramCounts c;
  const json& fetches = j.at("fetches");
  for (const auto& f : static_fields::kFetches) c.fetches.*f.member = fetches.value(f.name, 0.0);
  for (const auto& f : static_fields::kCounts)
    c.*f.member = f.required ? j.at(f.name).get<double>() : j.value(f.name, 0.0);
  if (j.contains("loops"))
    for (const auto& f : static_fields::kLoops) c.*f.member = j.at("loops").value(f.name, 0);
  return c;
}

ClassCounts classes_from(const json& j) {
  ClassCounts k;
  for (const auto& f : static_fields::kClasses) k.*f.member = j.value(f.name, 0.0);
  return k;
}

}  // namespace

json to_json(const std::optional<StaticCost>& cost) {
  if (!cost) return json::object();
  json out = {{"ao", counts_json(cost->ao)},
              {"passes", counts_json(cost->passes)},
              {"weighted", {{"ao", classes_json(cost->weighted_ao)}, {"others", classes_json(cost->weighted_others)}}}};
  for (const auto& f : static_fields::kCost) out[f.name] = (*cost).*f.member;
  return out;
}

std::optional<StaticCost> static_cost_from_json(const json& j) {
  if (j.is_null() || (j.is_object() && j.empty())) return std::nullopt;
  const char* member = "ao";
  try {
    StaticCost s;
    s.ao = counts_from(j.at("ao"));
    member = "passes";
    s.passes = counts_from(j.at("passes"));
    for (const auto& f : static_fields::kCost) {
      member = f.name;
      s.*f.member = j.value(f.name, 0.0);
    }
    member = "weighted";
    if (j.contains("weighted")) {
      s.weighted_ao = classes_from(j.at("weighted").at("ao"));
      s.weighted_others = classes_from(j.at("weighted").at("others"));
    }
    return s;
  } catch (const json::exception& e) {
    throw std::runtime_error(std::string("static.") + member + ": " + e.what());
  }
}

}  // namespace aovar::table
