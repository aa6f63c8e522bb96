// `aovar diff --json`: the typed TableDiff the text is written from, as JSON (NaN and infinities: null).
#include "decide/diff.h"
#include "decide/time_compare.h"
#include "util/schema.h"

namespace aovar::decide {

namespace {
using nlohmann::json;

json delta_json(const Delta& d) {
  return {{"key", d.key},
          {"a", d.a},
          {"b", d.b},
          {"pct", d.pct},
          {"pct_ci", interval_json(d.pct_ci)},
          {"verdict", d.verdict},
          {"by_threshold", d.by_threshold}};
}

json deltas_json(const std::vector<Delta>& list) {
  json out = json::array();
  for (const auto& d : list) out.push_back(delta_json(d));
  return out;
}

json metric_json(const MetricDiff& m) {
  return {{"metric", m.metric},
          {"higher_is_better", m.higher_is_better},
          {"helped", m.helped},
          {"hurt", m.hurt},
          {"unchanged", m.unchanged},
          {"inconclusive", m.inconclusive},
          {"by_threshold", m.by_threshold},
          {"total_a", m.total_a},
          {"total_b", m.total_b},
          {"mean_pct", m.mean_pct},
          {"top_helped", deltas_json(m.top_helped)},
          {"top_hurt", deltas_json(m.top_hurt)},
          {"rows", deltas_json(m.rows)}};
}
}  // namespace

json to_json(const TableDiff& d, const std::string& name_a, const std::string& name_b) {
  json metrics = json::array();
  for (const auto& m : d.metrics) metrics.push_back(metric_json(m));
  return {{"schema_version", util::kSchemaVersion},
          {"tool", "aovar diff"},
          {"a", name_a},
          {"b", name_b},
          {"common", d.common},
          {"only_a", d.only_a},
          {"only_b", d.only_b},
          {"metrics", metrics}};
}

}  // namespace aovar::decide
