#pragma once
// The elimination rule of `aovar ship`'s race (issue 35; the idea of F-race, Birattari et al. 2002): a
// candidate leaves the race once another one is both faster beyond the noise (decide/time_compare.h: its
// 95 % interval of the time ratio excludes 1) and strictly more accurate, each aggregated over the views the
// race is run on (their worst, as `aovar select` aggregates). A candidate tied on time with everything more
// accurate stays: the next round, with more repetitions, may still separate them. With a GPU target the time
// is the deterministic estimate, so "faster" is simply a smaller estimate.
// On a measured backend "beyond the noise" also needs a margin: the whole 95 % interval of the slowdown above
// `min_ratio`. A run's interval describes its own rounds, not the drift between runs on a loaded host, which
// ranked three eliminations of 1.02x-1.17x the other way in an exhaustive sweep (bench/README.md, bench/search).
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "table/table.h"

namespace aovar::ship {

struct Elimination {
  std::string variant, backend;
  std::string by;      // the variant that dominates it
  std::string reason;  // "slower than X beyond the noise (1.21x [1.10, 1.33], paired rounds) with more error (0.071 > 0.064)"
};

// The margin the rule applies: `margin` on a measured backend, 1 with a GPU target (an estimate has no noise).
double margin_in_force(const std::string& target, double margin);

// Every candidate of `rows` (one per variant and backend; rows without an error, or without an estimate on
// `target` when one is given, are not candidates) that another candidate dominates as above. Sorted by variant.
// `min_ratio` (>= 1) applies to measured times only: a target's estimate has no noise.
std::vector<Elimination> dominated_beyond_noise(const table::CostTable& rows, const std::string& target = "",
                                                double min_ratio = 1.0);

// The variants whose rows in `rows` copy an eliminated one's (same_code_as: the same code on that backend, so no
// candidacy of their own; measure/same_code.h), eliminated with it: the same dominating variant, the reason
// prefixed with "runs the same code as KEY, ". Sorted by variant.
std::vector<Elimination> same_code_eliminations(const table::CostTable& rows, const std::vector<Elimination>& eliminated);

// The race's order (measure::TimingPlan::race_order): on each view, a candidate's rank is how many of the
// screen's candidates were both more accurate and faster there (rel_time_median, the screen's few rounds); the
// screen's front (rank 0) is timed first. The race retires a row only against a more accurate one timed in
// its batch or before it, so the likely front goes first. The order decides only when a row is timed, never
// whether it is: a wrong guess costs rounds, not a candidate. (The static estimate ranks the Vulkan CPU backend's times at
// rho 0.44, bench/gpu; the screen has timed every candidate by then.)
std::shared_ptr<const std::map<std::pair<std::string, std::string>, int>> screen_ranks(const table::CostTable& screen);

}  // namespace aovar::ship
