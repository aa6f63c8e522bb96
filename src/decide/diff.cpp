#include "decide/diff.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "decide/time_compare.h"
#include "util/fs.h"

namespace aovar::decide {

namespace {

using RowMap = std::map<std::string, const table::CostRow*>;

// How one common row changed: +1 helped, -1 hurt, 0 unchanged / inconclusive.
struct Verdict {
  int sign = 0;
  bool inconclusive = false, by_threshold = false;
  // Time by rounds: the change as the ratio to the baseline gives it (free of the drift between the runs,
  // which the two tables' times keep) with its interval. NaN: the change of the values.
  double pct = NAN;
  util::Interval pct_ci;
};

double pct_of(double a, double b) {
  const double delta = b - a;
  return a != 0 ? 100.0 * delta / std::abs(a) : delta == 0 ? 0.0 : std::copysign(INFINITY, delta);
}

int threshold_sign(double a, double b, bool relative, double threshold, bool higher_better) {
  const double delta = b - a;
  const bool changed = relative ? (a == 0 ? delta != 0 : std::abs(delta) > threshold * std::abs(a))
                                : std::abs(delta) > threshold;
  if (!changed) return 0;
  return (higher_better ? delta > 0 : delta < 0) ? 1 : -1;
}

// Time: b against a beyond the noise. The rows come from two runs: on one scale compare_time compares their
// ratios to the baseline, which cancel the drift between the runs (Mann-Whitney on the two rows' rounds).
Verdict time_verdict(const table::CostRow& a, const table::CostRow& b) {
  if (!a.rounds.ratios.empty() && !b.rounds.ratios.empty()) {
    const TimeComparison t = compare_time(b, a);
    if (t.ci.known()) {
      Verdict v;
      v.sign = t.verdict == TimeVerdict::faster ? 1 : t.verdict == TimeVerdict::slower ? -1 : 0;
      v.inconclusive = t.tied();
      v.pct = 100 * (t.ratio - 1);
      v.pct_ci = {100 * (t.ci.lo - 1), 100 * (t.ci.hi - 1)};
      return v;
    }
  }
  Verdict v;
  v.sign = threshold_sign(a.time_ms.decision(), b.time_ms.decision(), true, 0.02, false);
  v.by_threshold = true;
  return v;
}

// The error is deterministic (one render against the reference): a fixed absolute threshold.
Verdict error_verdict(double a, double b, bool higher_better) {
  Verdict v;
  v.sign = threshold_sign(a, b, false, 1e-4, higher_better);
  return v;
}

struct Spec {
  const char* name;
  bool higher_better;
  bool (*has)(const table::CostRow&);
  double (*get)(const table::CostRow&);
  Verdict (*judge)(const table::CostRow&, const table::CostRow&);
};

const Spec kSpecs[] = {
    {"time_ms", false, [](const table::CostRow& r) { return !r.predicted; },
     [](const table::CostRow& r) { return r.time_ms.decision(); }, time_verdict},
    {"error.rmse", false, [](const table::CostRow& r) { return r.error.has_value(); },
     [](const table::CostRow& r) { return r.error->rmse; },
     [](const table::CostRow& a, const table::CostRow& b) { return error_verdict(a.error->rmse, b.error->rmse, false); }},
    {"error.ssim", true, [](const table::CostRow& r) { return r.error.has_value(); },
     [](const table::CostRow& r) { return r.error->ssim; },
     [](const table::CostRow& a, const table::CostRow& b) { return error_verdict(a.error->ssim, b.error->ssim, true); }},
};

void keep_top(std::vector<Delta>& list) {
  std::sort(list.begin(), list.end(), [](const Delta& x, const Delta& y) {
    double ax = std::abs(x.pct), ay = std::abs(y.pct);
    return ax != ay ? ax > ay : x.key < y.key;
  });
  if (list.size() > 10) list.resize(10);
}

MetricDiff diff_metric(const Spec& s, const RowMap& ra, const RowMap& rb) {
  MetricDiff m;
  m.metric = s.name;
  m.higher_is_better = s.higher_better;
  double pct_sum = 0;
  int pct_n = 0;
  for (const auto& [k, x] : ra) {
    auto it = rb.find(k);
    if (it == rb.end() || !s.has(*x) || !s.has(*it->second)) continue;
    const Verdict v = s.judge(*x, *it->second);
    Delta dl{k, s.get(*x), s.get(*it->second), 0, v.pct_ci};
    dl.pct = std::isnan(v.pct) ? pct_of(dl.a, dl.b) : v.pct;
    dl.verdict = v.sign > 0 ? "helped" : v.sign < 0 ? "hurt" : v.inconclusive ? "inconclusive" : "unchanged";
    dl.by_threshold = v.by_threshold;
    m.rows.push_back(dl);
    m.total_a += dl.a;
    m.total_b += dl.b;
    if (std::isfinite(dl.pct)) {
      pct_sum += dl.pct;
      ++pct_n;
    }
    m.by_threshold += v.by_threshold ? 1 : 0;
    if (v.sign == 0) {
      ++(v.inconclusive ? m.inconclusive : m.unchanged);
      continue;
    }
    (v.sign > 0 ? m.top_helped : m.top_hurt).push_back(dl);
  }
  m.helped = static_cast<int>(m.top_helped.size());
  m.hurt = static_cast<int>(m.top_hurt.size());
  m.mean_pct = pct_n ? pct_sum / pct_n : 0;
  keep_top(m.top_helped);
  keep_top(m.top_hurt);
  return m;
}

}  // namespace

TableDiff diff_tables(const table::CostTable& a, const table::CostTable& b) {
  RowMap ra, rb;
  for (const auto& r : a.rows) ra.emplace(r.key(), &r);
  for (const auto& r : b.rows) rb.emplace(r.key(), &r);
  TableDiff d;
  for (const auto& [k, r] : ra)
    if (!rb.count(k)) d.only_a.push_back(k);
  for (const auto& [k, r] : rb)
    if (!ra.count(k)) d.only_b.push_back(k);
  for (const auto& [k, r] : ra) d.common += rb.count(k) ? 1 : 0;
  for (const Spec& s : kSpecs) d.metrics.push_back(diff_metric(s, ra, rb));
  return d;
}

namespace {
std::string pct_text(double p) {
  if (std::isinf(p)) return p > 0 ? "+inf%" : "-inf%";
  return fmt::format("{:+.2f}%", p);
}

std::string delta_text(const Delta& dl) {
  std::string ci = dl.pct_ci.known() ? fmt::format(" [{:+.2f}%, {:+.2f}%]", dl.pct_ci.lo, dl.pct_ci.hi) : "";
  return fmt::format("    {}: {:.6g} -> {:.6g} ({}{})\n", dl.key, dl.a, dl.b, pct_text(dl.pct), ci);
}

std::string counts_text(const MetricDiff& m) {
  if (m.metric != "time_ms")
    return fmt::format("  helped: {}  hurt: {}  unchanged: {}\n", m.helped, m.hurt, m.unchanged);
  std::string s = fmt::format(
      "  helped {}, hurt {}, inconclusive {} (beyond the noise: the change of the ratio to the baseline, with its "
      "95 % interval)\n",
      m.helped, m.hurt, m.inconclusive);
  if (m.by_threshold)
    s += fmt::format("  {} rows without rounds decided by |change| > 2 % instead ({} of them unchanged)\n",
                     m.by_threshold, m.unchanged);
  return s;
}
}  // namespace

std::string format_diff(const TableDiff& d, const std::string& name_a, const std::string& name_b) {
  std::string s = fmt::format("A: {}\nB: {}\nrows in both: {}, only in A: {}, only in B: {}\n", name_a, name_b,
                              d.common, d.only_a.size(), d.only_b.size());
  for (const auto& m : d.metrics) {
    int n = m.helped + m.hurt + m.unchanged + m.inconclusive;
    double total_pct = m.total_a != 0 ? 100.0 * (m.total_b - m.total_a) / std::abs(m.total_a) : 0;
    s += fmt::format("\n{}{} ({} is better; {} rows)\n", m.metric, m.metric == "time_ms" ? " (paired, else min)" : "",
                     m.higher_is_better ? "higher" : "lower", n);
    s += counts_text(m);
    if (n) {
      s += fmt::format("  total: {:.6g} -> {:.6g} ({})\n", m.total_a, m.total_b, pct_text(total_pct));
      s += fmt::format("  mean: {:.6g} -> {:.6g}, mean change {}\n", m.total_a / n, m.total_b / n, pct_text(m.mean_pct));
    }
    for (const auto* list : {&m.top_helped, &m.top_hurt}) {
      if (list->empty()) continue;
      s += fmt::format("  {} (top {}):\n", list == &m.top_helped ? "helped" : "hurt", list->size());
      for (const auto& dl : *list) s += delta_text(dl);
    }
  }
  auto list_keys = [&](const char* title, const std::vector<std::string>& keys) {
    if (keys.empty()) return;
    s += fmt::format("\n{} ({}):\n", title, keys.size());
    for (const auto& k : keys) s += "  " + k + "\n";
  };
  list_keys("only in A", d.only_a);
  list_keys("only in B", d.only_b);
  return s;
}

}  // namespace aovar::decide
