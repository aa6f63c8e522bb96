// bench/confidence: are the time verdicts of --reps auto repeatable, and how many pairs do they resolve?
//
// Reads cost_table.json of two independent sweeps (RUN1, RUN2: same selection and options, no reuse between
// them) and optionally a third (--reps 10, for comparison), and compares every two variants of the same
// scene, view and backend with decide::compare_time, the tool's own verdict. Prints:
//   agreement:        of the pairs RUN1 declares different (not tied), the share whose order RUN2 keeps
//                     (its ratio on the same side of 1), and how many RUN2 declares the other way round
//   resolving power:  of all pairs, how many each run declares different
//   widths:           per run, the relative 95 % half-width of each row's ratio to the baseline (median,
//                     max) and the rounds it took (median, max); bench/confidence adds meta.reps_reached
// Rows sharing another row's measurement (same_code_as) and predicted rows are left out: their pairs say
// nothing about the timing. Exits 1 when the agreement is below 99 %.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "smoke.h"

#include "decide/time_compare.h"
#include "measure/timing.h"
#include "table/row_intervals.h"
#include "table/table.h"
#include "util/stats.h"

namespace {
using namespace aovar;

using Group = std::tuple<std::string, std::string, std::string>;  // scene, view, backend

// The measured rows of a table by group and variant, intervals recomputed from their rounds.
std::map<Group, std::map<std::string, table::CostRow>> load(const char* path) {
  std::map<Group, std::map<std::string, table::CostRow>> out;
  for (auto& r : table::read_table(path).rows) {
    if (r.predicted || !r.same_code_as.empty()) continue;
    table::set_intervals(r);
    out[{r.scene, r.view, r.backend}].emplace(r.variant, r);
  }
  return out;
}

struct Pair {
  const table::CostRow *a, *b;
};
std::vector<Pair> pairs(const std::map<Group, std::map<std::string, table::CostRow>>& run) {
  std::vector<Pair> out;
  for (const auto& [g, rows] : run)
    for (auto i = rows.begin(); i != rows.end(); ++i)
      for (auto j = std::next(i); j != rows.end(); ++j) out.push_back({&i->second, &j->second});
  return out;
}

const table::CostRow* find(const std::map<Group, std::map<std::string, table::CostRow>>& run, const table::CostRow& like) {
  auto g = run.find({like.scene, like.view, like.backend});
  if (g == run.end()) return nullptr;
  auto r = g->second.find(like.variant);
  return r == g->second.end() ? nullptr : &r->second;
}

double median(std::vector<double> v) { return v.empty() ? NAN : util::summarize(std::move(v)).median; }
double max_of(const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); }

// Widths and rounds of one run's rows (the baseline's ratios to itself left out).
void widths(const char* name, const std::map<Group, std::map<std::string, table::CostRow>>& run) {
  std::vector<double> hw, rounds;
  for (const auto& [g, rows] : run)
    for (const auto& [v, r] : rows) {
      if (r.rounds.is_baseline() || r.rounds.ratios.empty()) continue;
      const double w = measure::relative_half_width(r.rounds.ratios);
      if (std::isfinite(w)) hw.push_back(w);
      rounds.push_back(static_cast<double>(r.rounds.ratios.size()));
    }
  std::printf("%-6s %zu rows: 95 %% half-width median %.2f %%, max %.2f %%; rounds median %.0f, max %.0f\n", name,
              rounds.size(), 100 * median(hw), 100 * max_of(hw), median(rounds), max_of(rounds));
}

int resolved(const std::vector<Pair>& ps) {
  int n = 0;
  for (const auto& p : ps) n += decide::compare_time(*p.a, *p.b).tied() ? 0 : 1;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: aovar_confidence_bench RUN1/cost_table.json RUN2/cost_table.json [FIXED/cost_table.json]\n");
    return 2;
  }
  const auto run1 = load(argv[1]), run2 = load(argv[2]);
  const auto p1 = pairs(run1), p2 = pairs(run2);
  int different = 0, same_order = 0, reversed = 0, missing = 0;
  for (const auto& p : p1) {
    const auto c1 = decide::compare_time(*p.a, *p.b);
    if (c1.tied()) continue;
    ++different;
    const table::CostRow *a2 = find(run2, *p.a), *b2 = find(run2, *p.b);
    if (!a2 || !b2) {
      ++missing;
      continue;
    }
    const auto c2 = decide::compare_time(*a2, *b2);
    if ((c1.ratio < 1) == (c2.ratio < 1)) ++same_order;
    if (!c2.tied() && c2.verdict != c1.verdict) ++reversed;
  }
  const double agreement = different - missing > 0 ? static_cast<double>(same_order) / (different - missing) : 1.0;
  std::printf("agreement: %d of %d pairs run 1 declares different keep their order in run 2 (%.1f %%; target >= 99 %%); "
              "%d declared the other way round; %d not in run 2\n",
              same_order, different - missing, 100 * agreement, reversed, missing);
  std::printf("resolving power: run 1 %d of %zu pairs different, run 2 %d of %zu", resolved(p1), p1.size(), resolved(p2),
              p2.size());
  std::map<Group, std::map<std::string, table::CostRow>> fixed;
  if (argc > 3) {
    fixed = load(argv[3]);
    const auto pf = pairs(fixed);
    std::printf(", fixed %d of %zu", resolved(pf), pf.size());
  }
  std::printf("\n");
  widths("run 1", run1);
  widths("run 2", run2);
  if (argc > 3) widths("fixed", fixed);
  if (p1.empty()) {
    std::printf("no two variants on one view in run 1: nothing compared\n");
    return 1;
  }
  if (bench_smoke()) std::printf("(smoke: the 99 %% target is not judged)\n");
  return agreement >= 0.99 || bench_smoke() ? 0 : 1;
}
