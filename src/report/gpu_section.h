#pragma once
// The report's per-GPU part (issue 17): for each AMD family the cost table carries (sweep --gpu), the
// roofline estimate's ranking of the methods at each sample count, a per-pass table in the style of AMD's
// Radeon GPU Analyzer and Arm's Mali Offline Compiler (registers, occupancy, spills, instructions, the
// bound that limits each pass), the Sunet 2018 pairs re-judged by the estimate, and how the estimate's
// ranking agrees with the other families' and with the measured (CPU-rasteriser) time.
#include <string>
#include <vector>

#include "report/report.h"
#include "table/table.h"

namespace aovar::report {

std::vector<std::string> gpu_families(const table::CostTable& table);  // every family any row has, sorted

// One method at one sample count, like for like: the variant whose other axes agree most with the table's
// most common value of each axis (ties: the lower est_ms, then the key).
struct MethodEstimate {
  std::string algorithm, samples, variant;
  double est_ms = 0;
  double rmse = NAN;   // the worst over the variant's rows with an error (NaN: none)
  std::string bound;   // "<slowest pass>:<its bound>"
};
// Per sample count in `samples` that the table has, the methods sorted by est_ms on `family`.
std::vector<std::vector<MethodEstimate>> method_ranking(const table::CostTable& table, const std::string& family,
                                                        const std::vector<std::string>& samples = {"8", "16"});

// Spearman rank correlation of est_ms between two families over the variants both have (n: how many).
struct RankAgreement {
  std::string a, b;  // families, or a family and "scene/view/backend" of a measured group
  double rho = NAN;
  int n = 0;
};
std::vector<RankAgreement> family_agreement(const table::CostTable& table);
// est_ms on each family against each measured group's decision time, over that group's rows.
std::vector<RankAgreement> measured_agreement(const table::CostTable& table);

// The Sunet 2018 pairs with est_ms on `family` as the time.
std::vector<PairFinding> gpu_seed_pairs(const table::CostTable& table, const std::string& family);

// The sections for report.md and report.html ("" when no row has a GPU cost).
std::string gpu_markdown(const table::CostTable& table);
std::string gpu_html(const table::CostTable& table);

}  // namespace aovar::report
