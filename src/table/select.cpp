#include "table/select.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace aovar::table {

namespace {

// The time a query decides by: measured (paired, else min), or the estimate on the target GPU (NaN: none).
double time_of(const CostRow& r, const SelectQuery& q) {
  if (q.target.empty()) return r.time_ms.decision();
  auto it = r.gpu.find(q.target);
  return it == r.gpu.end() ? NAN : it->second.est_ms;
}

// The families any row has an estimate for, for the error that names them.
std::string families_of(const CostTable& table) {
  std::set<std::string> f;
  for (const auto& r : table.rows)
    for (const auto& [family, cost] : r.gpu)
      if (std::isfinite(cost.est_ms)) f.insert(family);
  std::string out;
  for (const auto& name : f) out += (out.empty() ? "" : ", ") + name;
  return out.empty() ? "none" : out;
}

}  // namespace

std::vector<Candidate> candidates(const CostTable& table, const SelectQuery& q) {
  std::map<std::pair<std::string, std::string>, Candidate> by;
  for (const auto& r : table.rows) {
    if (!r.error || r.predicted) continue;
    const double time = time_of(r, q);
    if (!std::isfinite(time)) continue;
    if (!q.scene.empty() && r.scene != q.scene) continue;
    if (!q.view.empty() && r.view != q.view) continue;
    if (!q.backend.empty() && r.backend != q.backend) continue;
    std::string where = r.scene + "/" + r.view;
    auto [it, fresh] = by.try_emplace({r.variant, r.backend});
    Candidate& c = it->second;
    if (fresh) {
      c = {r.variant, r.backend, time, r.error->rmse, r.error->ssim, {}, where, where};
    } else {
      if (r.error->rmse > c.rmse) {
        c.rmse = r.error->rmse;
        c.ssim = r.error->ssim;
        c.worst_error_view = where;
      }
      if (time > c.time_ms) {
        c.time_ms = time;
        c.worst_time_view = where;
      }
    }
    c.views.push_back(where);
  }
  std::vector<Candidate> out;
  for (auto& [k, c] : by) out.push_back(std::move(c));
  return out;
}

namespace {

std::string describe(const Candidate& c, const SelectQuery& q) {
  return fmt::format("{} [{}]  {:.3f} ms{}  rmse {:.5f}  ssim {:.4f}", c.variant, c.backend, c.time_ms,
                     q.target.empty() ? "" : " est. on " + q.target, c.rmse, c.ssim);
}

std::string pct(double delta, double base) {
  if (base == 0) return delta == 0 ? "+0.0%" : "n/a";
  return fmt::format("{:+.1f}%", 100.0 * delta / base);
}

bool by_error(const Candidate& a, const Candidate& b) {
  return std::tie(a.rmse, a.time_ms, a.variant, a.backend) < std::tie(b.rmse, b.time_ms, b.variant, b.backend);
}
bool by_time(const Candidate& a, const Candidate& b) {
  return std::tie(a.time_ms, a.rmse, a.variant, a.backend) < std::tie(b.time_ms, b.rmse, b.variant, b.backend);
}

}  // namespace

Selection select(const CostTable& table, const SelectQuery& q) {
  if (q.budget_ms.has_value() == q.max_error.has_value())
    throw std::runtime_error("select: give exactly one of --budget-ms and --max-error");
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
  bool budget = q.budget_ms.has_value();
  std::vector<Candidate> ok;
  for (const auto& c : all)
    if (budget ? c.time_ms <= *q.budget_ms : c.rmse <= *q.max_error) ok.push_back(c);
  std::sort(ok.begin(), ok.end(), budget ? by_error : by_time);

  Selection s;
  std::string scope = q.view.empty() ? "worst view of each variant (max rmse, max time over its views)"
                                     : "view " + q.view;
  if (!q.target.empty()) scope += "; time: the roofline estimate on " + q.target;
  if (ok.empty()) {
    std::vector<Candidate> sorted = all;
    std::sort(sorted.begin(), sorted.end(), budget ? by_time : by_error);
    s.nearest = sorted.front();
    s.text = budget ? fmt::format("no variant fits the budget of {:.3f} ms ({} candidates, {}); the fastest is {}\n",
                                  *q.budget_ms, all.size(), scope, describe(*s.nearest, q))
                    : fmt::format("no variant reaches rmse <= {:.5f} ({} candidates, {}); the lowest error is {}\n",
                                  *q.max_error, all.size(), scope, describe(*s.nearest, q));
    return s;
  }
  s.ok = true;
  s.choice = ok.front();
  for (std::size_t i = 1; i < ok.size() && i <= 3; ++i) s.runners_up.push_back(ok[i]);
  const Candidate& c = *s.choice;
  s.text = "choice: " + describe(c, q) + "\n";
  s.text += budget ? fmt::format("reason: lowest rmse of the {} of {} candidates within {:.3f} ms ({})\n", ok.size(),
                                 all.size(), *q.budget_ms, scope)
                   : fmt::format("reason: cheapest ({}) of the {} of {} candidates with rmse <= {:.5f} ({})\n",
                                 q.target.empty() ? "paired time" : "roofline estimate on " + q.target, ok.size(),
                                 all.size(), *q.max_error, scope);
  if (c.views.size() > 1)
    s.text += fmt::format("worst views: rmse {}, time {}\n", c.worst_error_view, c.worst_time_view);
  // Differences of 1-2 % are within what these machines reproduce; a much cheaper (or much better)
  // variant that nearly ties on the other criterion is the one an engineer would often ship.
  for (const auto& o : ok) {
    bool nearly_ties = budget ? o.time_ms <= 0.95 * c.time_ms && o.rmse <= c.rmse * (1 + q.tolerance)
                              : o.rmse <= 0.95 * c.rmse && o.time_ms <= c.time_ms * (1 + q.tolerance);
    if (nearly_ties && (!s.consider || (budget ? o.time_ms < s.consider->time_ms : o.rmse < s.consider->rmse)))
      s.consider = o;
  }
  if (s.consider) {
    const Candidate& o = *s.consider;
    s.text += fmt::format("consider: {} [{}] is {} in time with {} rmse ({:.3f} ms, rmse {:.5f}; tolerance {:.0f}%)\n",
                          o.variant, o.backend, pct(o.time_ms - c.time_ms, c.time_ms), pct(o.rmse - c.rmse, c.rmse),
                          o.time_ms, o.rmse, 100 * q.tolerance);
  }
  if (s.runners_up.empty()) {
    s.text += "runners-up: none (the only candidate that satisfies the request)\n";
    return s;
  }
  const Candidate& next = s.runners_up.front();
  double dt = next.time_ms - c.time_ms, de = next.rmse - c.rmse;
  s.text += budget ? fmt::format("margin: the runner-up has rmse {:+.5f} ({}) at {:+.3f} ms ({})\n", de,
                                 pct(de, c.rmse), dt, pct(dt, c.time_ms))
                   : fmt::format("margin: the runner-up costs {:+.3f} ms ({}) with rmse {:+.5f} ({})\n", dt,
                                 pct(dt, c.time_ms), de, pct(de, c.rmse));
  s.text += "runners-up:\n";
  for (std::size_t i = 0; i < s.runners_up.size(); ++i) s.text += fmt::format("  {}. {}\n", i + 2, describe(s.runners_up[i], q));
  return s;
}

}  // namespace aovar::table
