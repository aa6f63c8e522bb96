#include "report/seed_pairs.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "decide/time_compare.h"

namespace aovar::report {
namespace {
using table::CostRow;
using table::CostTable;

struct Spec {
  const char *title, *axis, *a, *b, *seed;
  int expected;  // +1: the seed found b slower than a; -1: faster
  // Axes besides `axis` that may differ within a pair: SAO reads only depth, so it meets Alchemy's G-buffer
  // configurations as the SAO paper compared them. Empty: every other axis equal.
  std::vector<std::string> free_axes = {};
};

const std::vector<Spec>& specs() {
  static const std::vector<Spec> s = {
      {"RG vs RGB normals", "normals", "rgb8", "rg8",
       "Sunet 2018, §5.6: savings negligible (G-buffer 6.4 -> 6.2 ms, AO 17.5 -> 17.6 ms); RGB kept as faster overall", +1},
      {"position buffer vs depth", "position", "depth", "position",
       "Sunet 2018, §5.5: a depth buffer is slightly faster for most shaders; for StarCraft II the position buffer is faster", +1},
      {"inverse projection vs similar triangles", "reconstruct", "similar_triangles", "inverse_projection",
       "Sunet 2018, §5.4: quality difference negligible; similar triangles slightly faster (AO 17.9 vs 19.83 ms)", +1},
      {"r32f vs r16f depth", "depth_format", "r16f", "r32f",
       "Sunet 2018, §5.3: quality difference negligible; 32-bit costs a little more in G-buffer, AO and blur", +1},
      {"progressive vs full", "progressive", "false", "true",
       "Sunet 2018, §5.9: progressive significantly faster for every method, despite a ~1.1 ms averaging pass", -1},
      {"bilateral vs separable blur", "blur", "separable", "bilateral",
       "Sunet 2018, §5.7: quality difference negligible; the separable blur is faster", +1},
      {"8 vs 16 samples", "samples", "8", "16",
       "McGuire et al. 2012, §4: vary the sample and blur taps to trade run time against spatial and temporal noise", +1},
      // The one pair that names methods, on purpose: it checks the SAO paper's own comparison (McGuire et al.
      // 2012, Table 1), so it is SAO and Alchemy or nothing; the pair is empty when a table lacks either.
      {"SAO vs Alchemy", "algorithm", "alchemy", "sao",
       "McGuire et al. 2012, Table 1: SAO 2.26 ms against AlchemyAO 16.10 ms at 2560x1600 (7.1x faster)", -1,
       {"normals", "position", "reconstruct", "depth_format"}},
  };
  return s;
}

// Row pairs (a, b) of a spec: the same scene, view and backend, and the same value of every axis but the
// spec's own and its free ones.
std::vector<std::pair<const CostRow*, const CostRow*>> matched(const CostTable& t, const Spec& sp) {
  // Hashed: the keys are long and share their start, so a sorted map spent most of report's time comparing
  // them (1,000,000 rows, 8 specs). The groups with a pair are sorted once at the end.
  using Group = std::map<std::string, std::vector<const CostRow*>>;  // by the spec axis' value
  std::unordered_map<std::string, Group> by_rest;
  for (const auto& r : t.rows) {
    auto it = r.axes.find(sp.axis);
    if (it == r.axes.end() || (it->second != sp.a && it->second != sp.b) || !r.same_code_as.empty()) continue;
    std::string rest = r.scene + "|" + r.view + "|" + r.backend;
    for (const auto& [k, v] : r.axes)
      if (k != sp.axis && std::find(sp.free_axes.begin(), sp.free_axes.end(), k) == sp.free_axes.end())
        rest += "|" + k + "=" + v;
    by_rest[rest][it->second].push_back(&r);
  }
  // In the order of their keys, as before: the medians do not depend on it, but the median pair shown does
  // when two pairs' ratios tie.
  std::vector<const std::pair<const std::string, Group>*> paired;
  for (const auto& group : by_rest)
    if (group.second.count(sp.a) && group.second.count(sp.b)) paired.push_back(&group);
  std::sort(paired.begin(), paired.end(), [](const auto* x, const auto* y) { return x->first < y->first; });
  std::vector<std::pair<const CostRow*, const CostRow*>> out;
  for (const auto* group : paired)
    for (const CostRow* a : group->second.at(sp.a))
      for (const CostRow* b : group->second.at(sp.b)) out.emplace_back(a, b);
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

// Verdicts per pair, then the finding's: most decisive pairs one way and none the other.
void judge(PairFinding& f, std::vector<decide::TimeComparison> cmp) {
  if (cmp.empty()) {
    f.verdict = "-";
    return;
  }
  for (const auto& c : cmp) {
    const int sign = c.verdict == decide::TimeVerdict::slower ? +1 : c.verdict == decide::TimeVerdict::faster ? -1 : 0;
    (sign == 0 ? f.inconclusive : sign == f.expected ? f.reproduced : f.refuted) += 1;
  }
  std::sort(cmp.begin(), cmp.end(), [](const auto& x, const auto& y) { return x.ratio < y.ratio; });
  const auto& mid = cmp[(cmp.size() - 1) / 2];
  f.ratio = mid.ratio;
  f.ci = mid.ci;
  const int n = static_cast<int>(cmp.size());
  f.verdict = f.refuted == 0 && 2 * f.reproduced > n   ? "reproduced"
              : f.reproduced == 0 && 2 * f.refuted > n ? "refuted"
                                                       : "inconclusive here";
}

std::vector<PairFinding> findings(const CostTable& t, const TimeOf& time_of) {
  std::vector<PairFinding> out;
  for (const auto& sp : specs()) {
    PairFinding f;
    f.title = sp.title;
    f.axis = sp.axis;
    f.a = sp.a;
    f.b = sp.b;
    f.seed = sp.seed;
    f.expected = sp.expected;
    std::vector<double> dt, de;
    std::vector<decide::TimeComparison> cmp;
    for (const auto& [ra, rb] : matched(t, sp)) {
      const double ta = time_of ? time_of(*ra) : measured_time(*ra), tb = time_of ? time_of(*rb) : measured_time(*rb);
      if (!(ta > 0) || !(tb > 0)) continue;
      dt.push_back(100.0 * (tb - ta) / ta);
      if (ra->error && rb->error) de.push_back(rb->error->rmse - ra->error->rmse);
      // An estimate has no rounds: its comparison is the point's (compare_time does that for rows without).
      decide::TimeComparison c = time_of ? decide::TimeComparison{tb / ta, {}, tb < ta   ? decide::TimeVerdict::faster
                                                                             : tb > ta ? decide::TimeVerdict::slower
                                                                                       : decide::TimeVerdict::tied,
                                                                "point estimates"}
                                        : decide::compare_time(*rb, *ra);
      cmp.push_back(c);
      ++f.pairs;
    }
    f.time_delta_pct = median(dt);
    f.rmse_delta = median(de);
    judge(f, std::move(cmp));
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

double measured_time(const CostRow& r) { return r.predicted ? NAN : r.time_ms.decision(); }

std::vector<PairFinding> seed_pairs(const CostTable& t) { return findings(t, {}); }
std::vector<PairFinding> seed_pairs(const CostTable& t, const TimeOf& time_of) { return findings(t, time_of); }

Grid pairs_grid(const std::vector<PairFinding>& pairs, const std::string& what) {
  Grid g{{"pair", "matched", what + " b / a (median pair) [95 %]", "pairs: same / opposite / inconclusive", "verdict",
          "RMSE Δ (median)", "the seed found"},
         {false, true, true, true, false, true, false},
         {}};
  for (const auto& f : pairs) {
    std::string ratio = !f.pairs ? "–"
                        : f.ci.known() ? fmt::format("{:.3f} [{:.3f}, {:.3f}]", f.ratio, f.ci.lo, f.ci.hi)
                                       : fmt::format("{:.3f}", f.ratio);
    g.rows.push_back({fmt::format("{} ({} → {})", f.title, f.a, f.b), std::to_string(f.pairs), ratio,
                      f.pairs ? fmt::format("{} / {} / {}", f.reproduced, f.refuted, f.inconclusive) : "–", f.verdict,
                      f.pairs ? fmt::format("{:+.4f}", f.rmse_delta) : "–", f.seed});
  }
  return g;
}

}  // namespace aovar::report
