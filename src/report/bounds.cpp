// What the reports show of a large table (bounds.h).
#include "report/bounds.h"

#include <fmt/format.h>

namespace aovar::report {

std::vector<const table::CostRow*> charted(const std::vector<const table::CostRow*>& rows, std::size_t cap) {
  if (rows.size() <= cap) return rows;
  std::vector<bool> keep(rows.size(), false);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < rows.size() && kept < cap; ++i)
    if (rows[i]->pareto) keep[i] = true, ++kept;
  const std::size_t others = rows.size() - kept, places = cap - kept;
  if (places > 0)  // the k-th of `places` evenly spaced among the rows not yet kept
    for (std::size_t i = 0, seen = 0, next = 0; i < rows.size() && next < places; ++i) {
      if (keep[i]) continue;
      if (seen++ == next * others / places) keep[i] = true, ++next;
    }
  std::vector<const table::CostRow*> out;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (keep[i]) out.push_back(rows[i]);
  return out;
}

std::string left_out(std::size_t shown, std::size_t total, const std::string& what) {
  if (shown >= total) return "";
  return fmt::format("(showing {} of {} {}; cost_table.json has them all)", shown, total, what);
}

}  // namespace aovar::report
