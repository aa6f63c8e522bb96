#pragma once
// Static costs of the variants a sweep selects: each one's typed StaticCost (table/static_cost.h) from the
// Vulkan SPIR-V of its fragment programs (src/analyze), its axes and the hash of its programs.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "measure/measure.h"
#include "table/static_cost.h"
#include "table/table.h"

namespace aovar::sweep {

struct VariantStatic {
  table::StaticCost cost;
  std::map<std::string, std::string> axes;
  std::string vulkan_programs;  // equal to the Vulkan backend's rows' spirv_hash: variants with the same programs
  std::string same_as;          // the first variant with identical programs and pipeline (itself when none)
};

// A row for variant `key` where `like` was measured (its scene, view, backend, size, threads), with the
// variant's axes, static cost and (Vulkan) programs hash: nothing measured, for the cost model to predict.
table::CostRow unmeasured_row(const table::CostRow& like, const std::string& key, const VariantStatic& vs);

// Of the variants `globs` select (exact keys are globs too), but `exclude`; compiled with the measurement's
// manifest, cache and jobs. Throws std::runtime_error when a program fails to compile.
std::map<std::string, VariantStatic> static_costs(const measure::MeasureOptions& mo, const std::vector<std::string>& globs,
                                                  const std::set<std::string>& exclude = {});

}  // namespace aovar::sweep
