// --reps auto as the rows and the run report it (measure.h): what each row's timing reached, and over rows.
#include <algorithm>

#include <fmt/format.h>

#include "measure/measure.h"
#include "util/stats.h"

namespace aovar::measure {

std::string reps_text(const MeasureOptions& o) {
  if (o.timing.still_only) return "still";  // a row without time is not a timed row to reuse
  if (!o.timing.auto_reps) return std::to_string(o.timing.reps);  // as before --reps auto: fixed-count rows stay reusable
  const AutoReps& a = *o.timing.auto_reps;
  // A raced row may stop before its target: not the row a plain --reps auto gives.
  std::string race = o.timing.races() ? fmt::format(":race{}", o.timing.race_margin) : std::string();
  if (o.timing.race_budget) race += ":budget";
  return fmt::format("auto:min{}:ci{}:cap{}s:max{}{}", o.timing.reps, a.ci_target, a.cap_s, a.max_rounds, race);
}

std::string reps_words(const MeasureOptions& o) {
  if (o.timing.still_only) return "no timing (the still only)";
  if (!o.timing.auto_reps) return fmt::format("{} reps", o.timing.reps);
  return fmt::format("--reps auto (95 % interval within {:g} %, at least {} rounds, cap {:g} s or {} rounds{})",
                     100 * o.timing.auto_reps->ci_target, o.timing.reps, o.timing.auto_reps->cap_s, o.timing.auto_reps->max_rounds,
                     o.timing.races()
                         ? fmt::format("; raced: stopped once slower beyond {:.2f}x than a more accurate one{}", o.timing.race_margin,
                                       o.timing.race_budget ? " or than the budget's variant" : "")
                         : std::string());
}

nlohmann::json reps_auto_json(const MeasureOptions& o) {
  if (!o.timing.auto_reps) return nullptr;
  return {{"min_rounds", o.timing.reps}, {"ci_target", o.timing.auto_reps->ci_target}, {"cap_s", o.timing.auto_reps->cap_s},
          {"max_rounds", o.timing.auto_reps->max_rounds}};
}

RepsReached reps_reached(const MeasureResult& result) {
  RepsReached r;
  for (const auto& row : result.rows) r.add(row);
  return r;
}

void MeasureRow::set_reps_reached(Stop why) {
  stop = why;
  ci_half_width = relative_half_width(rounds.ratios);
}

void RepsReached::add(const MeasureRow& row) {
  if (row.is_baseline) return;
  ++rows;
  if (row.stop == Stop::cap) ++on_cap;
  if (row.stop == Stop::dominated) ++dominated;  // left unresolved on purpose: not the widest that matters
  else if (std::isfinite(row.ci_half_width)) widest = std::max(widest, row.ci_half_width);
  rounds.push_back(static_cast<double>(row.rounds.ratios.size()));
}

nlohmann::json RepsReached::to_json() const {
  const util::TimeStats r = util::summarize(rounds);
  return {{"rows", rows}, {"on_cap", on_cap}, {"dominated", dominated}, {"widest_half_width", widest},
          {"rounds_median", rounds.empty() ? 0.0 : r.median},
          {"rounds_max", rounds.empty() ? 0.0 : *std::max_element(rounds.begin(), rounds.end())}};
}

std::string RepsReached::text() const {
  if (rounds.empty()) return "no timed rows";
  return fmt::format("widest 95 % half-width {:.1f} %, {} of {} rows on the cap{}, rounds median {:.0f}, max {:.0f}",
                     100 * widest, on_cap, rows, dominated ? fmt::format(", {} stopped as dominated", dominated) : "",
                     util::summarize(rounds).median, *std::max_element(rounds.begin(), rounds.end()));
}

}  // namespace aovar::measure
