#include "ship/race.h"

#include <algorithm>

#include <fmt/format.h>

#include "table/select.h"
#include "table/time_compare.h"

namespace aovar::ship {

std::vector<Elimination> dominated_beyond_noise(const table::CostTable& rows, const std::string& target) {
  table::SelectQuery q;
  q.target = target;
  std::vector<table::Candidate> cs = table::candidates(rows, q);
  // Most accurate first: only a candidate earlier in this order can dominate a later one, and the first
  // dominator found is the most accurate one faster beyond the noise.
  std::stable_sort(cs.begin(), cs.end(), [](const table::Candidate& a, const table::Candidate& b) { return a.rmse < b.rmse; });
  std::vector<Elimination> out;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    for (std::size_t j = 0; j < i && cs[j].rmse < cs[i].rmse; ++j) {
      const table::TimeComparison c = table::compare_candidates(cs[j], cs[i], q);
      if (c.verdict != table::TimeVerdict::faster) continue;
      const table::TimeComparison slower = table::compare_candidates(cs[i], cs[j], q);
      out.push_back({cs[i].variant, cs[i].backend, cs[j].variant,
                     fmt::format("slower than {} beyond the noise ({}, {}) with more error ({:.4f} > {:.4f})", cs[j].variant,
                                 table::ratio_text(slower), slower.method, cs[i].rmse, cs[j].rmse)});
      break;
    }
  }
  std::sort(out.begin(), out.end(), [](const Elimination& a, const Elimination& b) {
    return std::tie(a.variant, a.backend) < std::tie(b.variant, b.backend);
  });
  return out;
}

}  // namespace aovar::ship
