#pragma once
// Is one row faster than another, beyond the noise? Every time comparison aovar makes (Pareto, select, diff,
// the seed pairs) goes through compare_time, which turns two rows' rounds (table::Rounds) into the ratio of
// their times with a 95 % interval and a verdict: an interval that holds 1 is a tie (docs/confidence.md).
#include <string>

#include "table/table.h"
#include "util/intervals.h"

namespace aovar::decide {

enum class TimeVerdict { faster, slower, tied };
const char* verdict_name(TimeVerdict v);  // "faster", "slower", "tied"

struct TimeComparison {
  double ratio = 0;     // a's time / b's time
  util::Interval ci;    // 95 %; unknown when either row has no rounds (then the verdict is the point's)
  TimeVerdict verdict = TimeVerdict::tied;
  // How: "paired rounds" (one batch: round i against round i), "against the baseline" (one of them is the
  // baseline: the other's own interval), "separate rounds" (Mann-Whitney on the two rows' rounds),
  // "disjoint intervals" (each row's own intervals do not overlap), "point estimates" (no rounds).
  const char* method = "";
  bool tied() const { return verdict == TimeVerdict::tied; }
};

// a against b. Rows on the same scale (table::Rounds::scale) are compared by their ratios to the shared baseline,
// which cancels the drift between rounds and runs; other rows (two views of select's worst view) by their
// paired times.
TimeComparison compare_time(const table::CostRow& a, const table::CostRow& b);

// "1.042x [1.013, 1.071]" or "1.042x" when the interval is unknown.
std::string ratio_text(const TimeComparison& c);

// An interval in the decisions' --json documents (select, diff): {"lo": .., "hi": ..}, null when unknown. A cost
// table writes its intervals as [lo, hi] pairs instead (table::to_json).
nlohmann::json interval_json(const util::Interval& ci);

}  // namespace aovar::decide
