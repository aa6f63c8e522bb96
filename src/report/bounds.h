#pragma once
// How much of a large table the reports show (issue 34, point 5): a 1,000,000-row table made a 161 MB
// report.html (a circle per row in two charts per group). Tables list at most kMaxListed rows of a front,
// the image grid kMaxImaged, and charts kMaxCharted points: every front row first, then rows spread evenly
// over the rest by time; each bounded section says what it left out. cost_table.* keep every row.
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "table/table.h"

namespace aovar::report {

inline constexpr std::size_t kMaxListed = 100;
inline constexpr std::size_t kMaxImaged = 24;
inline constexpr std::size_t kMaxCharted = 2000;

// At most `cap` of `rows` (sorted by time): all when they fit; else the front rows (up to cap) and, for the
// places left, rows at even steps through the others, in the input order.
std::vector<const table::CostRow*> charted(const std::vector<const table::CostRow*>& rows, std::size_t cap = kMaxCharted);

// The first `cap` of `rows`.
template <class T>
std::vector<T> first(const std::vector<T>& rows, std::size_t cap) {
  return {rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(std::min(cap, rows.size()))};
}

// "" when shown == total; else "(showing 100 of 2,345 <what>; cost_table.json has them all)".
std::string left_out(std::size_t shown, std::size_t total, const std::string& what);

}  // namespace aovar::report
