#include "table/static_cost.h"

#include <stdexcept>

namespace aovar::table {
namespace {
using json = nlohmann::json;

json counts_json(const ProgramCounts& c) {
  const FetchCounts& f = c.fetches;
  return {{"fetches", {{"depth", f.depth}, {"normal", f.normal}, {"position", f.position}, {"input", f.input},
                       {"history", f.history}, {"prefilter", f.prefilter}}},
          {"alu", c.alu}, {"fma", c.fma}, {"div", c.div}, {"transcendental", c.transcendental},
          {"cmp_select", c.cmp_select}, {"branches", c.branches}, {"unprojections", c.unprojections},
          {"projections", c.projections},
          {"loops", {{"constant", c.constant_loops}, {"dynamic", c.dynamic_loops}, {"unrolled", c.unrolled_loops}}}};
}

json classes_json(const ClassCounts& k) {
  return {{"fetches", k.fetches}, {"prefilter_fetches", k.prefilter_fetches}, {"alu", k.alu},
          {"transcendental", k.transcendental}, {"div", k.div}, {"cmp_select", k.cmp_select}, {"branches", k.branches}};
}

ProgramCounts counts_from(const json& j) {
  ProgramCounts c;
  const json& f = j.at("fetches");
  c.fetches = {f.value("depth", 0.0), f.value("normal", 0.0), f.value("position", 0.0), f.value("input", 0.0),
               f.value("history", 0.0), f.value("prefilter", 0.0)};
  c.alu = j.at("alu");
  c.fma = j.value("fma", 0.0);
  c.div = j.value("div", 0.0);
  c.transcendental = j.at("transcendental");
  c.cmp_select = j.value("cmp_select", 0.0);
  c.branches = j.value("branches", 0.0);
  c.unprojections = j.value("unprojections", 0.0);
  c.projections = j.value("projections", 0.0);
  if (j.contains("loops")) {
    const json& l = j.at("loops");
    c.constant_loops = l.value("constant", 0);
    c.dynamic_loops = l.value("dynamic", 0);
    c.unrolled_loops = l.value("unrolled", 0);
  }
  return c;
}

ClassCounts classes_from(const json& j) {
  return {j.value("fetches", 0.0),        j.value("prefilter_fetches", 0.0), j.value("alu", 0.0),
          j.value("transcendental", 0.0), j.value("div", 0.0),               j.value("cmp_select", 0.0),
          j.value("branches", 0.0)};
}

}  // namespace

json to_json(const std::optional<StaticCost>& cost) {
  if (!cost) return json::object();
  return {{"ao", counts_json(cost->ao)},
          {"passes", counts_json(cost->passes)},
          {"ao_bytes_per_pixel", cost->ao_bytes_per_pixel},
          {"work_per_pixel", cost->work_per_pixel},
          {"weighted", {{"ao", classes_json(cost->weighted_ao)}, {"others", classes_json(cost->weighted_others)}}}};
}

std::optional<StaticCost> static_cost_from_json(const json& j) {
  if (j.is_null() || (j.is_object() && j.empty())) return std::nullopt;
  const char* member = "ao";
  try {
    StaticCost s;
    s.ao = counts_from(j.at("ao"));
    member = "passes";
    s.passes = counts_from(j.at("passes"));
    member = "ao_bytes_per_pixel";
    s.ao_bytes_per_pixel = j.value("ao_bytes_per_pixel", 0.0);
    member = "work_per_pixel";
    s.work_per_pixel = j.value("work_per_pixel", 0.0);
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
