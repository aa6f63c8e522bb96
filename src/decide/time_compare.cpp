#include "decide/time_compare.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "table/row_intervals.h"

namespace aovar::decide {
namespace {

TimeVerdict verdict_of(double ratio, const util::Interval& ci) {
  if (!ci.known()) return ratio < 1 ? TimeVerdict::faster : ratio > 1 ? TimeVerdict::slower : TimeVerdict::tied;
  return ci.hi < 1 ? TimeVerdict::faster : ci.lo > 1 ? TimeVerdict::slower : TimeVerdict::tied;
}

TimeComparison make(double ratio, util::Interval ci, const char* method) {
  return {ratio, ci, verdict_of(ratio, ci), method};
}

// The median of the per-round ratios with its sign-test interval: a row against the baseline, or two rows of
// one batch (ratio_i = a_i / b_i).
TimeComparison from_ratios(std::vector<double> ratios, const char* method) {
  std::vector<double> copy = ratios;
  const double median = util::summarize(std::move(copy)).median;
  return make(median, util::median_interval(std::move(ratios)), method);
}

std::vector<double> log_times(const table::CostRow& r, double scale) {
  std::vector<double> out;
  for (double x : r.rounds.ratios) out.push_back(std::log(x * scale));
  return out;
}

TimeComparison separate(const table::CostRow& a, const table::CostRow& b, bool same_scale) {
  // On one scale the baseline min cancels; across scales the times are on each row's own baseline.
  const double sa = same_scale ? 1 : table::paired_scale_ms(a), sb = same_scale ? 1 : table::paired_scale_ms(b);
  util::Shift s = util::shift_interval(log_times(a, sa), log_times(b, sb));
  util::Interval ci = s.ci.known() ? util::Interval{std::exp(s.ci.lo), std::exp(s.ci.hi)} : util::Interval{};
  return make(std::exp(s.estimate), ci, "separate rounds");
}

bool has_rounds(const table::CostRow& r) {
  return !r.rounds.ratios.empty() && (!r.rounds.is_baseline() || r.time_ms.paired > 0);
}

}  // namespace

const char* verdict_name(TimeVerdict v) {
  switch (v) {
    case TimeVerdict::faster: return "faster";
    case TimeVerdict::slower: return "slower";
    case TimeVerdict::tied: break;
  }
  return "tied";
}

TimeComparison compare_time(const table::CostRow& a, const table::CostRow& b) {
  const double ta = a.time_ms.decision(), tb = b.time_ms.decision();
  if (!has_rounds(a) || !has_rounds(b) || a.predicted || b.predicted || tb <= 0)
    return make(tb > 0 ? ta / tb : 1, {}, "point estimates");
  const bool same_scale = !a.rounds.scale.empty() && a.rounds.scale == b.rounds.scale;
  // Rows whose own intervals do not overlap differ whatever the pairing; this also keeps a front over
  // thousands of rows cheap (the pairwise interval is computed only where the two overlap). On one scale
  // the intervals of the ratios to the baseline, which are free of the drift between runs (diff compares
  // two runs); across scales the paired times'.
  const util::Interval& ia = same_scale ? a.rel_time_ci : a.time_ms.paired_ci;
  const util::Interval& ib = same_scale ? b.rel_time_ci : b.time_ms.paired_ci;
  if (ia.known() && ib.known() && (ia.hi < ib.lo || ib.hi < ia.lo)) {
    const double ratio = same_scale ? a.rel_time_median / b.rel_time_median : ta / tb;
    return {ratio, {ia.lo / ib.hi, ia.hi / ib.lo}, ia.hi < ib.lo ? TimeVerdict::faster : TimeVerdict::slower,
            "disjoint intervals"};
  }
  if (same_scale && a.rounds.is_baseline() && b.rounds.is_baseline()) return make(1, {1, 1}, "against the baseline");
  if (same_scale && b.rounds.is_baseline()) return from_ratios(a.rounds.ratios, "against the baseline");
  if (same_scale && a.rounds.is_baseline()) {
    std::vector<double> inverse;
    for (double r : b.rounds.ratios) inverse.push_back(1 / r);
    return from_ratios(std::move(inverse), "against the baseline");
  }
  if (same_scale && a.rounds.id == b.rounds.id) {
    // One batch: round i of both, over the rounds both took part in (--reps auto stops rows at different rounds).
    std::vector<double> ratios;
    for (std::size_t i = 0; i < std::min(a.rounds.ratios.size(), b.rounds.ratios.size()); ++i)
      ratios.push_back(a.rounds.ratios[i] / b.rounds.ratios[i]);
    return from_ratios(std::move(ratios), "paired rounds");
  }
  return separate(a, b, same_scale);
}

std::string ratio_text(const TimeComparison& c) {
  if (!c.ci.known()) return fmt::format("{:.3f}x", c.ratio);
  return fmt::format("{:.3f}x [{:.3f}, {:.3f}]", c.ratio, c.ci.lo, c.ci.hi);
}

nlohmann::json interval_json(const util::Interval& ci) {
  return ci.known() ? nlohmann::json{{"lo", ci.lo}, {"hi", ci.hi}} : nlohmann::json(nullptr);
}

}  // namespace aovar::decide
