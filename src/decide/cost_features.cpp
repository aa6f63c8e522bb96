#include "decide/cost_features.h"

#include <string>

namespace aovar::decide {

FeatureSpec static_features() {
  FeatureSpec f;
  f.names = {"ao.fetches", "ao.alu", "ao.transcendental", "passes.alu", "passes.fetches", "work_per_pixel"};
  f.extract = [](const table::CostRow& r) {
    if (!r.static_cost) return std::vector<double>(6, 0.0);
    const table::StaticCost& s = *r.static_cost;
    return std::vector<double>{s.ao.fetches.total(), s.ao.alu,          s.ao.transcendental,
                               s.passes.alu,         s.passes.fetches.total(), s.work_per_pixel};
  };
  return f;
}

FeatureSpec compact_features() {
  FeatureSpec f;
  f.names = {"work_per_pixel", "ao.fetches*res2", "res2", "blur.separable", "blur.bilateral", "progressive"};
  f.extract = [](const table::CostRow& r) {
    auto axis = [&](const char* k) {
      auto it = r.axes.find(k);
      return it == r.axes.end() ? std::string() : it->second;
    };
    double res = axis("resolution").empty() ? 1.0 : std::stod(axis("resolution"));
    double fetches = r.static_cost ? r.static_cost->ao.fetches.total() : 0.0;
    double work = r.static_cost ? r.static_cost->work_per_pixel : 0.0;
    return std::vector<double>{work, fetches * res * res, res * res, axis("blur") == "separable" ? 1.0 : 0.0,
                               axis("blur") == "bilateral" ? 1.0 : 0.0, axis("progressive") == "true" ? 1.0 : 0.0};
  };
  return f;
}

FeatureSpec weighted_class_features() {
  static const char* classes[] = {"alu", "transcendental", "div", "cmp_select", "branches"};
  FeatureSpec f;
  f.names = {"ao.gbuffer_fetches", "ao.prefilter_fetches"};
  for (const char* c : classes) f.names.push_back(std::string("ao.") + c);
  f.names.push_back("others.fetches");
  for (const char* c : classes) f.names.push_back(std::string("others.") + c);
  f.extract = [](const table::CostRow& r) {
    if (!r.static_cost) return std::vector<double>(13, 0.0);
    const table::ClassCounts& ao = r.static_cost->weighted_ao;
    const table::ClassCounts& others = r.static_cost->weighted_others;
    auto five = [](const table::ClassCounts& k) { return std::vector<double>{k.alu, k.transcendental, k.div, k.cmp_select, k.branches}; };
    std::vector<double> x = {ao.fetches - ao.prefilter_fetches, ao.prefilter_fetches};
    for (double v : five(ao)) x.push_back(v);
    x.push_back(others.fetches);
    for (double v : five(others)) x.push_back(v);
    return x;
  };
  return f;
}

}  // namespace aovar::decide
