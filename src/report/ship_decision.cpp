#include "report/ship_decision.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "table/on_views.h"

namespace aovar::report {
using nlohmann::json;
using table::CostRow;
using table::CostTable;

namespace {

std::optional<CostRow> row_of(const CostTable& held_out, const std::string& variant, const std::string& view) {
  for (const CostRow& r : held_out.rows)
    if (r.variant == variant && r.view == view) return r;
  return std::nullopt;
}

// The timing baseline's key: the rounds' scale is "<baseline>@<scene>/<view>/...".
std::string timing_baseline(const CostRow& row) {
  const std::string& scale = row.rounds.scale;
  const auto at = scale.find('@');
  return at == std::string::npos ? std::string() : scale.substr(0, at);
}

std::optional<BaselineComparison> compare_with_baseline(const CostTable& held_out, const decide::Selection& s,
                                                        const CostRow& choice_row) {
  const decide::SelectQuery& q = s.query;
  BaselineComparison b;
  b.variant = !q.budget_of.empty() ? q.budget_of : timing_baseline(choice_row);
  if (b.variant.empty()) return std::nullopt;
  if (b.variant == s.choice->variant) {
    b.time = "1x (the choice is the baseline)";
    b.rmse_delta = 0.0;
    return b;
  }
  for (const decide::Candidate& c : decide::candidates(held_out, q)) {
    if (c.variant != b.variant || c.backend != s.choice->backend) continue;
    b.time = decide::ratio_text(decide::compare_candidates(*s.choice, c, q));
    b.rmse_delta = s.choice->rmse - c.rmse;
    b.row = row_of(held_out, c.variant, choice_row.view);
    return b;
  }
  // Not scored on the held-out views (a baseline timed only to pair the rounds): its paired ratio still holds.
  if (!q.target.empty() || choice_row.rel_time_median <= 0) return std::nullopt;
  const util::Interval& ci = choice_row.rel_time_ci;
  b.time = ci.known() ? fmt::format("{:.3f}x [{:.3f}, {:.3f}]", choice_row.rel_time_median, ci.lo, ci.hi)
                      : fmt::format("{:.3f}x", choice_row.rel_time_median);
  return b;
}

int int_of(const json& ship, const char* key) {
  const auto it = ship.find(key);
  return it != ship.end() && it->is_number_integer() ? it->get<int>() : 0;
}

std::vector<FunnelStage> funnel_of(const json& ship) {
  std::vector<FunnelStage> f;
  const int selected = int_of(ship, "selected");
  f.push_back({"space", selected, 0, "the variants --variants selects"});
  int left = selected;
  if (const auto p = ship.find("pruned"); p != ship.end() && p->is_object()) {
    const table::PruningCounts counts = table::pruning_counts_from_json(*p);
    const std::string rules = counts.rules_text();
    f.push_back({"profile", counts.kept, counts.dropped,
                 "what the scene cannot need" + (rules.empty() ? std::string() : " (" + rules + ")")});
    left = counts.kept;
  }
  const int lean = int_of(ship, "lean_dropped");
  left -= lean;
  f.push_back({"normals lean", left, lean, ship.value("normals_lean_evidence", std::string())});
  for (const json& round : ship.value("rounds", json::array())) {
    const int candidates = round.value("candidates", 0), eliminated = round.value("eliminated", 0);
    f.push_back({round.value("name", std::string("round")), candidates - eliminated, eliminated,
                 round.value("timing", std::string())});
  }
  if (const auto h = ship.find("holdout_timing"); h != ship.end() && h->is_object()) {
    const int timed = h->value("timed", 0);
    const int untimed = h->contains("untimed") && (*h)["untimed"].is_array() ? int((*h)["untimed"].size()) : 0;
    f.push_back({"held-out", timed, untimed, h->value("rule", std::string())});
  }
  return f;
}

}  // namespace

std::string query_text(const decide::SelectQuery& q) {
  if (!q.budget_of.empty()) return "budget: no slower than " + q.budget_of;
  if (q.budget_ms) return fmt::format("budget: {:.3f} ms", *q.budget_ms);
  if (q.max_error) return fmt::format("error target: RMSE at most {:.4f}", *q.max_error);
  return "no criterion";
}

namespace {

// One choice of meta.ship: its target, and its query asked again of the rows it was decided on.
ShipDecision decision_on(const CostTable& t, const json& ship, const std::string& target, const json& query) {
  ShipDecision d;
  d.scene = ship.value("scene", std::string());
  d.target = target;
  d.backend = ship.value("backend", std::string());
  d.holdout_views = ship.value("holdout_views", std::vector<std::string>{});
  d.build_line = ship.value("build_line", std::string());
  d.funnel = funnel_of(ship);
  const CostTable held_out = table::decided_rows(t, target);
  d.selection = decide::select(held_out, decide::query_from_json(query));
  if (d.selection.choice && !d.holdout_views.empty()) {
    d.choice_row = row_of(held_out, d.selection.choice->variant, d.holdout_views.front());
    if (d.choice_row) d.baseline = compare_with_baseline(held_out, d.selection, *d.choice_row);
  }
  return d;
}

}  // namespace

std::vector<ShipDecision> ship_decisions(const CostTable& t) {
  const json& ship = t.meta.ship;
  if (!ship.is_object()) return {};
  try {
    std::vector<ShipDecision> out;
    if (ship.contains("choices")) {
      for (const json& c : ship.at("choices")) out.push_back(decision_on(t, ship, c.at("target").get<std::string>(), c.at("query")));
    } else if (ship.contains("query")) {  // a table written before ship searched for several targets
      out.push_back(decision_on(t, ship, ship.value("target", std::string()), ship.at("query")));
    }
    return out;
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("cost table meta.ship: ") + e.what());
  }
}

}  // namespace aovar::report
