#include "decide/select.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include "decide/top_set.h"

namespace aovar::decide {

namespace {

// The time a query decides by: measured (paired, else min), or the estimate on the target GPU (NaN: none).
double time_of(const table::CostRow& r, const SelectQuery& q) {
  if (q.target.empty()) return r.time_ms.decision();
  auto it = r.gpu.find(q.target);
  return it == r.gpu.end() ? NAN : it->second.est_ms;
}

// The families any row has an estimate for, for the error that names them.
std::string families_of(const table::CostTable& table) {
  std::set<std::string> f;
  for (const auto& r : table.rows)
    for (const auto& [family, cost] : r.gpu)
      if (std::isfinite(cost.est_ms)) f.insert(family);
  std::string out;
  for (const auto& name : f) out += (out.empty() ? "" : ", ") + name;
  return out.empty() ? "none" : out;
}

}  // namespace

std::vector<Candidate> candidates(const table::CostTable& table, const SelectQuery& q) {
  // Each candidate with its slowest row so far, copied into time_row once at the end (a row is kilobytes).
  std::map<std::pair<std::string, std::string>, std::pair<Candidate, const table::CostRow*>> by;
  for (const auto& r : table.rows) {
    // A same_code_as row is its representative's measurement again: the representative stands for both.
    if (!r.error || r.predicted || !r.same_code_as.empty()) continue;
    const double time = time_of(r, q);
    if (!std::isfinite(time)) continue;
    if (!q.scene.empty() && r.scene != q.scene) continue;
    if (!q.view.empty() && r.view != q.view) continue;
    if (!q.backend.empty() && r.backend != q.backend) continue;
    std::string where = r.scene + "/" + r.view;
    auto [it, fresh] = by.try_emplace({r.variant, r.backend});
    auto& [c, time_row] = it->second;
    if (fresh) {
      c.variant = r.variant;
      c.backend = r.backend;
      c.rmse = r.error->rmse;
      c.ssim = r.error->ssim;
      c.worst_error_view = where;
    } else if (r.error->rmse > c.rmse) {
      c.rmse = r.error->rmse;
      c.ssim = r.error->ssim;
      c.worst_error_view = where;
    }
    if (fresh || time > c.time_ms) {
      c.time_ms = time;
      c.worst_time_view = where;
      time_row = &r;
    }
    c.views.push_back(where);
  }
  std::vector<Candidate> out;
  for (auto& [k, candidate] : by) {
    auto& [c, time_row] = candidate;
    c.time_row = *time_row;
    // An estimate is deterministic: only a measured time has an interval.
    // The baseline's ratio to itself is 1 in every round: no interval of its own to show.
    if (q.target.empty() && !c.time_row.rounds.is_baseline()) c.time_ci = c.time_row.time_ms.paired_ci;
    if (c.time_row.static_cost) c.work_per_pixel = c.time_row.static_cost->work_per_pixel;
    out.push_back(std::move(c));
  }
  return out;
}

TimeComparison compare_candidates(const Candidate& a, const Candidate& b, const SelectQuery& q) {
  if (q.target.empty()) return compare_time(a.time_row, b.time_row);
  const double ratio = b.time_ms > 0 ? a.time_ms / b.time_ms : 1;
  return {ratio, {}, ratio < 1 ? TimeVerdict::faster : ratio > 1 ? TimeVerdict::slower : TimeVerdict::tied,
          "point estimates"};
}

namespace {

std::string interval_text(const util::Interval& ci) {
  return ci.known() ? fmt::format(" [{:.3f}, {:.3f}]", ci.lo, ci.hi) : "";
}

std::string describe(const Candidate& c, const SelectQuery& q) {
  return fmt::format("{} [{}]  {:.3f} ms{}{}  rmse {:.5f}  ssim {:.4f}", c.variant, c.backend, c.time_ms,
                     interval_text(c.time_ci), q.target.empty() ? "" : " est. on " + q.target, c.rmse, c.ssim);
}

std::string pct(double delta, double base) {
  if (base == 0) return delta == 0 ? "+0.0%" : "n/a";
  return fmt::format("{:+.1f}%", 100.0 * delta / base);
}

// A static cost that is not known sorts after every known one.
double work_key(const Candidate& c) { return std::isnan(c.work_per_pixel) ? INFINITY : c.work_per_pixel; }

bool by_error(const Candidate& a, const Candidate& b) {
  return std::tie(a.rmse, a.time_ms, a.variant, a.backend) < std::tie(b.rmse, b.time_ms, b.variant, b.backend);
}
bool by_time(const Candidate& a, const Candidate& b) {
  return std::tie(a.time_ms, a.rmse, a.variant, a.backend) < std::tie(b.time_ms, b.rmse, b.variant, b.backend);
}
// Among candidates tied on time: lowest error, then least static work, then the point time, then the key.
bool tie_order(const Candidate& a, const Candidate& b) {
  const double wa = work_key(a), wb = work_key(b);
  return std::tie(a.rmse, wa, a.time_ms, a.variant, a.backend) < std::tie(b.rmse, wb, b.time_ms, b.variant, b.backend);
}

bool faster(const Candidate& a, const Candidate& b, const SelectQuery& q) {
  return compare_candidates(a, b, q).verdict == TimeVerdict::faster;
}

// The members of `pool` no member outside them is faster than beyond the noise: the candidates tied on
// time. Ties do not chain (a ~ b, b ~ c, a faster than c) and the verdicts can form a cycle (a faster than
// b, b than c, c than a: medians of paired ratios are not transitive), so this is the Schwartz set of the
// "faster" verdicts (top_set.h, docs/confidence.md), never empty; without a cycle it is the candidates no
// other is faster than. The fastest point goes first: it beats most of a large table at once.
std::vector<Candidate> fastest_tied(const std::vector<Candidate>& pool, const SelectQuery& q) {
  if (pool.empty()) return {};
  const std::size_t fastest = static_cast<std::size_t>(std::min_element(pool.begin(), pool.end(), by_time) - pool.begin());
  std::vector<Candidate> out;
  for (std::size_t i : schwartz_set(pool.size(), fastest,
                                    [&](std::size_t a, std::size_t b) { return faster(pool[a], pool[b], q); }))
    out.push_back(pool[i]);
  std::sort(out.begin(), out.end(), tie_order);
  return out;
}

// `first`, then the members of `rest` not in it (in their order). A set of keys, not a scan of `first`: on a
// table of 100,000 candidates the scan was quadratic.
std::vector<Candidate> first_then_rest(std::vector<Candidate> first, std::vector<Candidate>&& rest) {
  std::set<std::pair<std::string, std::string>> placed;
  for (const auto& c : first) placed.insert({c.variant, c.backend});
  for (auto& c : rest)
    if (!placed.count({c.variant, c.backend})) first.push_back(std::move(c));
  return first;
}

// Max-error: the tied-fastest first (in tie order), then the rest by time.
std::vector<Candidate> order_max_error(std::vector<Candidate> ok, const SelectQuery& q, std::size_t& n_tied) {
  std::vector<Candidate> tied = fastest_tied(ok, q);
  n_tied = tied.size();
  std::sort(ok.begin(), ok.end(), by_time);
  return first_then_rest(std::move(tied), std::move(ok));
}

// Budget: by error; among the lowest-error ones (equal rmse), the tied-fastest first in tie order.
std::vector<Candidate> order_budget(std::vector<Candidate> ok, const SelectQuery& q) {
  std::sort(ok.begin(), ok.end(), by_error);
  auto group_end = std::find_if(ok.begin(), ok.end(), [&](const Candidate& c) { return c.rmse != ok.front().rmse; });
  std::vector<Candidate> group(ok.begin(), group_end);
  return first_then_rest(fastest_tied(group, q), std::move(ok));
}

std::string name_of(const Candidate& c, const Candidate& choice) {
  return c.backend == choice.backend ? c.variant : c.variant + " [" + c.backend + "]";
}

std::string tied_line(const Selection& s, bool budget) {
  if (s.tied.empty()) return "";
  std::string names;
  for (std::size_t i = 0; i < s.tied.size() && i < 10; ++i) names += (i ? ", " : "") + name_of(s.tied[i], *s.choice);
  if (s.tied.size() > 10) names += fmt::format(", and {} more", s.tied.size() - 10);
  return fmt::format("tied on time with {} other{} (intervals overlap): {}; {}\n", s.tied.size(),
                     s.tied.size() == 1 ? "" : "s", names,
                     budget ? "none of them has a lower rmse"
                            : "decided by lowest rmse, then work per pixel (static), then point time");
}

// The budget's "consider" test: faster beyond the noise. A comparison without an interval (no rounds, or
// a target's estimate) cannot show the noise, so it asks for the margin of 5 % these hosts reproduce
// (bench/HISTORY.md, "aovar select: what the machines reproduce") before a line is worth it.
bool clearly_faster(const Candidate& o, const Candidate& c, const SelectQuery& q) {
  const TimeComparison t = compare_candidates(o, c, q);
  return t.ci.known() ? t.verdict == TimeVerdict::faster : t.ratio <= 0.95;
}

void add_consider(Selection& s, const std::vector<Candidate>& ok, const SelectQuery& q, bool budget) {
  const Candidate& c = *s.choice;
  for (const auto& o : ok) {
    bool worth = budget ? o.rmse <= c.rmse * (1 + q.tolerance) && clearly_faster(o, c, q)
                        : o.rmse <= 0.95 * c.rmse && o.time_ms <= c.time_ms * (1 + q.tolerance);
    if (worth && (!s.consider || (budget ? o.time_ms < s.consider->time_ms : o.rmse < s.consider->rmse)))
      s.consider = o;
  }
  if (!s.consider) return;
  const Candidate& o = *s.consider;
  s.text += fmt::format(
      "consider: {} [{}] is {} in time with {} rmse ({:.3f} ms, rmse {:.5f}, time ratio {}; tolerance {:.0f}%)\n",
      o.variant, o.backend, pct(o.time_ms - c.time_ms, c.time_ms), pct(o.rmse - c.rmse, c.rmse), o.time_ms, o.rmse,
      ratio_text(compare_candidates(o, c, q)), 100 * q.tolerance);
}

void add_margin(Selection& s, const SelectQuery& q, bool budget) {
  const Candidate& c = *s.choice;
  const Candidate& next = s.runners_up.front();
  s.margin = compare_candidates(next, c, q);
  double dt = next.time_ms - c.time_ms, de = next.rmse - c.rmse;
  s.text += budget ? fmt::format("margin: the runner-up has rmse {:+.5f} ({}) at {:+.3f} ms ({})", de,
                                 pct(de, c.rmse), dt, pct(dt, c.time_ms))
                   : fmt::format("margin: the runner-up costs {:+.3f} ms ({}) with rmse {:+.5f} ({})", dt,
                                 pct(dt, c.time_ms), de, pct(de, c.rmse));
  s.text += fmt::format("; time ratio {}{}\n", ratio_text(*s.margin),
                        s.margin->tied() ? " (tied: the interval holds 1)" : "");
}

std::string scope_of(const SelectQuery& q) {
  std::string scope = q.view.empty() ? "worst view of each variant (max rmse, max time over its views)"
                                     : "view " + q.view;
  if (!q.target.empty()) scope += "; time: the estimate on " + q.target + " (gpu." + q.target + ".est_ms)";
  return scope;
}

Selection nothing_fits(const std::vector<Candidate>& all, const SelectQuery& q, bool budget) {
  Selection s;
  std::vector<Candidate> sorted = all;
  std::sort(sorted.begin(), sorted.end(), budget ? by_time : by_error);
  s.nearest = sorted.front();
  s.reason = budget ? fmt::format("no variant fits the budget of {:.3f} ms ({} candidates, {}); the fastest is {}",
                                  *q.budget_ms, all.size(), scope_of(q), describe(*s.nearest, q))
                    : fmt::format("no variant reaches rmse <= {:.5f} ({} candidates, {}); the lowest error is {}",
                                  *q.max_error, all.size(), scope_of(q), describe(*s.nearest, q));
  s.text = s.reason + "\n";
  return s;
}

std::vector<Candidate> checked_candidates(const table::CostTable& table, const SelectQuery& q) {
  if (q.budget_ms.has_value() == q.max_error.has_value())
    throw std::runtime_error("select: give exactly one of --budget-ms and --max-error");
  // NaN fits nothing and compares false everywhere: a malformed request, not "nothing fits".
  if (q.budget_ms && !(std::isfinite(*q.budget_ms) && *q.budget_ms > 0))
    throw std::runtime_error(fmt::format("select: --budget-ms {} is not a finite number of milliseconds > 0", *q.budget_ms));
  if (q.max_error && !(std::isfinite(*q.max_error) && *q.max_error >= 0))
    throw std::runtime_error(fmt::format("select: --max-error {} is not a finite rmse >= 0", *q.max_error));
  if (!(std::isfinite(q.tolerance) && q.tolerance >= 0))
    throw std::runtime_error(fmt::format("select: --tolerance {} is not a finite share >= 0", q.tolerance));
  std::vector<Candidate> all = candidates(table, q);
  if (all.empty() && !q.target.empty())
    throw std::runtime_error(fmt::format(
        "select: no row with an error has an estimate for GPU '{}' (this table has estimates for: {}; run aovar sweep "
        "--gpu {})",
        q.target, families_of(table), q.target));
  if (all.empty())
    throw std::runtime_error(fmt::format(
        "select: no measured row with an error matches scene '{}' view '{}' backend '{}' (omit a filter, or "
        "measure with --reference)",
        q.scene.empty() ? "*" : q.scene, q.view.empty() ? "*" : q.view, q.backend.empty() ? "*" : q.backend));
  return all;
}

// The choice, its ties and the first lines of the text, from the eligible candidates in decision order.
void choose(Selection& s, const std::vector<Candidate>& ordered, std::size_t n_tied, std::size_t n_all,
            const SelectQuery& q, bool budget) {
  s.ok = true;
  s.choice = ordered.front();
  const Candidate& c = *s.choice;
  s.choice_ci = c.time_ci;
  for (std::size_t i = 1; i < ordered.size() && i <= 3; ++i) s.runners_up.push_back(ordered[i]);
  if (budget) {
    for (std::size_t i = 1; i < ordered.size(); ++i)
      if (compare_candidates(ordered[i], c, q).tied()) s.tied.push_back(ordered[i]);
  } else {
    s.tied.assign(ordered.begin() + 1, ordered.begin() + n_tied);
  }
  s.text = "choice: " + describe(c, q) + "\n";
  // Only a budget query has a budget: --max-error leaves budget_ms empty (found by _GLIBCXX_ASSERTIONS).
  const std::string within = !budget                 ? std::string()
                             : q.budget_of.empty() ? fmt::format("within {:.3f} ms", *q.budget_ms)
                                                   : "not slower than " + q.budget_of + " beyond the noise";
  s.reason = budget ? fmt::format("lowest rmse of the {} of {} candidates {} ({})", ordered.size(), n_all, within,
                                  scope_of(q))
                    : fmt::format("cheapest ({}) of the {} of {} candidates with rmse <= {:.5f} ({})",
                                  q.target.empty() ? "paired time, within the noise" : "roofline estimate on " + q.target,
                                  ordered.size(), n_all, *q.max_error, scope_of(q));
  s.text += "reason: " + s.reason + "\n";
  s.text += tied_line(s, budget);
  if (budget && q.budget_of.empty() && c.time_ci.known() && c.time_ci.hi > *q.budget_ms) {
    s.may_exceed_budget = true;
    s.text += fmt::format("may exceed the budget: its 95 % interval reaches {:.3f} ms\n", c.time_ci.hi);
  }
  if (c.views.size() > 1)
    s.text += fmt::format("worst views: rmse {}, time {}\n", c.worst_error_view, c.worst_time_view);
}

// --budget-of: the named variant's time becomes budget_ms (throws when the table has no such candidate).
SelectQuery with_budget_of(const table::CostTable& table, SelectQuery q) {
  if (q.budget_of.empty()) return q;
  if (q.budget_ms || q.max_error)
    throw std::runtime_error("select: give exactly one of --budget-ms, --budget-of and --max-error");
  SelectQuery probe = q;
  probe.max_error = 1e300;  // any query, for the candidates
  for (const auto& c : candidates(table, probe))
    if (c.variant == q.budget_of) {
      q.budget_ms = c.time_ms;
      return q;
    }
  throw std::runtime_error(fmt::format("select --budget-of {}: no measured row with an error for this variant in the "
                                       "query's scope (aovar list shows the keys; the table must hold it)",
                                       q.budget_of));
}

// --budget-of: a candidate that fits only through a tie with the budget (its interval holds 1: often a row of
// few rounds, such as one the race retired early), yet is slower beyond the noise than a candidate that is
// slower than the budget beyond the noise, is slower than the budget as well: it does not fit. Checked against
// the kOverChecked fastest over-budget candidates, to bound the work on tables of 100,000 candidates.
constexpr std::size_t kOverChecked = 32;

void drop_slower_than_over_budget(std::vector<Candidate>& ok, const std::vector<bool>& tie_only,
                                  std::vector<Candidate> over, const SelectQuery& q) {
  if (over.empty()) return;
  std::sort(over.begin(), over.end(), by_time);
  if (over.size() > kOverChecked) over.resize(kOverChecked);
  std::vector<Candidate> kept;
  for (std::size_t i = 0; i < ok.size(); ++i) {
    const bool over_too = tie_only[i] && std::any_of(over.begin(), over.end(), [&](const Candidate& o) {
      const TimeComparison t = compare_candidates(ok[i], o, q);
      return t.ci.known() && t.verdict == TimeVerdict::slower;
    });
    if (!over_too) kept.push_back(std::move(ok[i]));
  }
  ok = std::move(kept);
}

Selection select_within(const table::CostTable& table, const SelectQuery& q) {
  const std::vector<Candidate> all = checked_candidates(table, q);
  const bool budget = q.budget_ms.has_value();
  // --budget-of: within the budget means not slower than that variant beyond the noise (its ties fit too).
  auto ref = std::find_if(all.begin(), all.end(), [&](const Candidate& c) { return c.variant == q.budget_of; });
  std::vector<Candidate> ok, over;
  std::vector<bool> tie_only;  // --budget-of, per `ok`: fits only through a tie with the budget (the budget never)
  for (const auto& c : all) {
    if (ref == all.end()) {
      if (budget ? c.time_ms <= *q.budget_ms : c.rmse <= *q.max_error) ok.push_back(c);
      continue;
    }
    const TimeVerdict v = compare_candidates(c, *ref, q).verdict;
    if (v == TimeVerdict::slower) {
      over.push_back(c);
      continue;
    }
    ok.push_back(c);
    tie_only.push_back(v == TimeVerdict::tied && &c != &*ref);
  }
  if (ref != all.end()) drop_slower_than_over_budget(ok, tie_only, std::move(over), q);
  if (ok.empty()) return nothing_fits(all, q, budget);
  std::size_t n_tied = 1;
  const std::vector<Candidate> ordered = budget ? order_budget(ok, q) : order_max_error(ok, q, n_tied);
  Selection s;
  choose(s, ordered, n_tied, all.size(), q, budget);
  add_consider(s, ordered, q, budget);
  if (s.runners_up.empty()) {
    s.text += "runners-up: none (the only candidate that satisfies the request)\n";
    return s;
  }
  add_margin(s, q, budget);
  s.text += "runners-up:\n";
  for (std::size_t i = 0; i < s.runners_up.size(); ++i) s.text += fmt::format("  {}. {}\n", i + 2, describe(s.runners_up[i], q));
  return s;
}


}  // namespace

Selection select(const table::CostTable& table, const SelectQuery& query) {
  const SelectQuery q = with_budget_of(table, query);
  Selection s = select_within(table, q);
  s.query = q;
  if (!q.budget_of.empty())
    s.text = fmt::format("budget: the time of {} ({:.3f} ms in this scope); variants tied with it fit too\n",
                         q.budget_of, *q.budget_ms) + s.text;
  return s;
}

}  // namespace aovar::decide
