#include "ship/race.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "decide/select.h"
#include "decide/time_compare.h"

namespace aovar::ship {

namespace {

// The slower one's whole interval (or, without rounds, its point ratio) lies above the margin.
bool beyond_margin(const decide::TimeComparison& slower, double min_ratio) {
  return slower.ci.known() ? slower.ci.lo >= min_ratio : slower.ratio >= min_ratio;
}

}  // namespace

double margin_in_force(const std::string& target, double margin) { return target.empty() ? margin : 1.0; }

std::vector<Elimination> dominated_beyond_noise(const table::CostTable& rows, const std::string& target,
                                                double min_ratio) {
  min_ratio = margin_in_force(target, min_ratio);
  decide::SelectQuery q;
  q.target = target;
  std::vector<decide::Candidate> cs = decide::candidates(rows, q);
  // Most accurate first: only a candidate earlier in this order can dominate a later one, and the first
  // dominator found is the most accurate one faster beyond the noise.
  std::stable_sort(cs.begin(), cs.end(), [](const decide::Candidate& a, const decide::Candidate& b) { return a.rmse < b.rmse; });
  std::vector<Elimination> out;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    for (std::size_t j = 0; j < i && cs[j].rmse < cs[i].rmse; ++j) {
      const decide::TimeComparison c = decide::compare_candidates(cs[j], cs[i], q);
      if (c.verdict != decide::TimeVerdict::faster) continue;
      const decide::TimeComparison slower = decide::compare_candidates(cs[i], cs[j], q);
      if (!beyond_margin(slower, min_ratio)) continue;
      out.push_back({cs[i].variant, cs[i].backend, cs[j].variant,
                     fmt::format("slower than {} beyond the noise{} ({}, {}) with more error ({:.4f} > {:.4f})", cs[j].variant,
                                 min_ratio > 1.0 ? fmt::format(" and the {:.2f}x margin", min_ratio) : std::string(),
                                 decide::ratio_text(slower), slower.method, cs[i].rmse, cs[j].rmse)});
      break;
    }
  }
  std::sort(out.begin(), out.end(), [](const Elimination& a, const Elimination& b) {
    return std::tie(a.variant, a.backend) < std::tie(b.variant, b.backend);
  });
  return out;
}

std::vector<Elimination> same_code_eliminations(const table::CostTable& rows, const std::vector<Elimination>& eliminated) {
  std::map<std::string, const Elimination*> by_variant;
  for (const auto& e : eliminated) by_variant[e.variant] = &e;
  std::map<std::string, Elimination> out;
  for (const auto& r : rows.rows) {
    auto it = by_variant.find(r.same_code_as);
    if (it == by_variant.end() || by_variant.count(r.variant)) continue;
    const Elimination& e = *it->second;
    out.try_emplace(r.variant, Elimination{r.variant, r.backend, e.by, "runs the same code as " + e.variant + ", " + e.reason});
  }
  std::vector<Elimination> list;
  for (auto& [k, e] : out) list.push_back(std::move(e));
  return list;
}

std::shared_ptr<const std::map<std::pair<std::string, std::string>, int>> screen_ranks(const table::CostTable& screen) {
  std::map<std::string, std::vector<const table::CostRow*>> by_view;
  for (const auto& r : screen.rows)
    if (r.error && std::isfinite(r.error->rmse) && r.rel_time_median > 0) by_view[r.view].push_back(&r);
  auto out = std::make_shared<std::map<std::pair<std::string, std::string>, int>>();
  for (const auto& [view, rows] : by_view)
    for (const table::CostRow* r : rows)
      (*out)[{r->variant, view}] = int(std::count_if(rows.begin(), rows.end(), [&](const table::CostRow* o) {
        return o->error->rmse < r->error->rmse && o->rel_time_median < r->rel_time_median;
      }));
  return out;
}

}  // namespace aovar::ship
