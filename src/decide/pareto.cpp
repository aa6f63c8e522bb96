// The Pareto front of time against error per scene, view and backend, and the worst view of each scene.
#include "decide/pareto.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "decide/time_compare.h"

namespace aovar::decide {

namespace {

// b is dominated by a: no more error, time lower or tied, and better in one of them beyond the noise.
bool dominates(const table::CostRow& a, const table::CostRow& b) {
  if (a.error->rmse > b.error->rmse) return false;
  const TimeComparison t = compare_time(a, b);
  if (t.verdict == TimeVerdict::slower) return false;
  return a.error->rmse < b.error->rmse || t.verdict == TimeVerdict::faster;
}

}  // namespace

void mark_pareto(std::vector<table::CostRow>& rows) {
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<table::CostRow*>> groups;
  for (auto& r : rows) {
    r.pareto = false;
    if (r.error && !std::isnan(r.error->rmse) && r.same_code_as.empty()) groups[{r.scene, r.view, r.backend}].push_back(&r);
  }
  for (auto& [g, members] : groups) {
    // In order of error: only rows before a row (error no higher) can dominate it. Ties make the relation
    // non-transitive, so each row is checked against every earlier one, not only against the front so far.
    std::sort(members.begin(), members.end(), [](const table::CostRow* a, const table::CostRow* b) {
      double ta = a->time_ms.decision(), tb = b->time_ms.decision();
      return std::tie(a->error->rmse, ta, a->variant) < std::tie(b->error->rmse, tb, b->variant);
    });
    // The fastest earlier row dominates most rows on its own: asking it first keeps a group of 100,000 rows
    // near linear (the full scan runs only for the rows it does not dominate, about the front's size). The
    // answer is the full scan's: the shortcut only ends it early when one dominator is found.
    const table::CostRow* fastest = nullptr;
    for (std::size_t i = 0; i < members.size(); ++i) {
      bool dominated = fastest && dominates(*fastest, *members[i]);
      for (std::size_t j = 0; j < members.size() && members[j]->error->rmse <= members[i]->error->rmse && !dominated; ++j)
        dominated = j != i && dominates(*members[j], *members[i]);
      members[i]->pareto = !dominated;
      if (!fastest || members[i]->time_ms.decision() < fastest->time_ms.decision()) fastest = members[i];
    }
  }
}

std::vector<table::CostRow> worst_view(const std::vector<table::CostRow>& rows) {
  std::map<std::tuple<std::string, std::string, std::string, std::string, int>, std::vector<const table::CostRow*>> groups;
  for (const auto& r : rows)
    if (r.error) groups[{r.scene, r.variant, r.backend, r.size, r.threads}].push_back(&r);
  std::vector<table::CostRow> out;
  for (const auto& [g, members] : groups) {
    std::vector<const table::CostRow*> sorted = members;
    std::sort(sorted.begin(), sorted.end(), [](const table::CostRow* a, const table::CostRow* b) { return a->view < b->view; });
    const table::CostRow* worst = sorted[0];
    const table::CostRow* slowest = sorted[0];
    table::CostRow agg = *worst;
    std::string views;
    for (const table::CostRow* r : sorted) {
      if (r->error->rmse > worst->error->rmse) worst = r;
      if (r->time_ms.decision() > slowest->time_ms.decision()) slowest = r;
      agg.time_ms.min = std::max(agg.time_ms.min, r->time_ms.min);
      agg.time_ms.median = std::max(agg.time_ms.median, r->time_ms.median);
      agg.time_ms.p90 = std::max(agg.time_ms.p90, r->time_ms.p90);
      agg.time_ms.n = std::min(agg.time_ms.n, r->time_ms.n);
      agg.time_ms.paired = std::max(agg.time_ms.paired, r->time_ms.paired);
      agg.rel_time = std::max(agg.rel_time, r->rel_time);
      agg.predicted = agg.predicted || r->predicted;
      agg.health.nan += r == sorted[0] ? 0 : r->health.nan;
      agg.health.inf += r == sorted[0] ? 0 : r->health.inf;
      agg.health.out_of_range += r == sorted[0] ? 0 : r->health.out_of_range;
      if (r->flicker) agg.flicker = std::max(agg.flicker.value_or(0.0), *r->flicker);
      views += (views.empty() ? "" : ",") + r->view;
    }
    agg.error = worst->error;
    // The decision time is the slowest view's, with its interval and rounds (compare_time pairs those; their
    // scale still names that view, so two worst rows from different views compare by paired time).
    agg.time_ms.paired = slowest->time_ms.paired;
    agg.time_ms.paired_ci = slowest->time_ms.paired_ci;
    agg.gbuffer_ms = slowest->gbuffer_ms;
    agg.rel_time_median = slowest->rel_time_median;
    agg.rel_time_ci = slowest->rel_time_ci;
    agg.rounds = slowest->rounds;
    agg.view = "worst(" + views + ")";
    agg.images.clear();
    out.push_back(std::move(agg));
  }
  // Front per (scene, backend): the aggregated rows' view names differ only by which views were present.
  std::map<std::pair<std::string, std::string>, std::vector<table::CostRow>> by;
  for (auto& r : out) by[{r.scene, r.backend}].push_back(r);
  out.clear();
  for (auto& [k, group] : by) {
    std::vector<std::string> views;
    for (auto& r : group) views.push_back(std::exchange(r.view, "worst"));
    mark_pareto(group);
    for (std::size_t i = 0; i < group.size(); ++i) {
      group[i].view = views[i];
      out.push_back(std::move(group[i]));
    }
  }
  return out;
}

}  // namespace aovar::decide
