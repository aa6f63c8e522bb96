#pragma once
// `sweep --prune-dominated` on one scene: measure a first share of the variants, fit the cost models, skip
// those predicted to be dominated, measure a check sample of them anyway and report whether any reached the
// Pareto front. The rule is written out in prune_dominated.cpp.
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "measure/measure.h"
#include "sweep/static_costs.h"
#include "sweep/sweep.h"

namespace aovar::sweep {

struct DominatedPruning {
  nlohmann::json report;                                  // meta.prune.scenes[]
  std::map<std::string, std::set<std::string>> checked;   // the check sample: reported name -> its identical variants
  std::set<std::string> phase1_measured;                  // inputs hashes measured by the seed phase
};

// Measures scene `mo.scene` in two phases (the rows of both, as one run_measure would return them).
measure::MeasureResult measure_pruned(const SweepOptions& o, const measure::MeasureOptions& mo,
                                      const std::map<std::string, VariantStatic>& statics, const std::string& folder,
                                      const measure::Progress& say, DominatedPruning& pruning);

// Would a checked variant have reached the front? Its rows against every row but the other checked variants'
// (which the rule would have skipped too), per view and backend: adds it to report.checked_on_front.
void check_front(DominatedPruning& pruning, const std::vector<table::CostRow>& rows);

}  // namespace aovar::sweep
