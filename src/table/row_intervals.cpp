#include "table/row_intervals.h"

#include "util/intervals.h"

namespace aovar::table {

double paired_scale_ms(const CostRow& r) {
  return r.rel_time_median > 0 && r.time_ms.paired > 0 ? r.time_ms.paired / r.rel_time_median : 0;
}

void set_intervals(CostRow& r) {
  r.rel_time_ci = {};
  r.time_ms.paired_ci = {};
  if (r.rounds.ratios.empty() || r.predicted) return;
  r.rel_time_ci = util::median_interval(r.rounds.ratios);
  const double scale = paired_scale_ms(r);
  if (r.rel_time_ci.known() && scale > 0) r.time_ms.paired_ci = {r.rel_time_ci.lo * scale, r.rel_time_ci.hi * scale};
}

}  // namespace aovar::table
