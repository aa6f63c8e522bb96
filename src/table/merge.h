#pragma once
// The join of shard tables (`aovar merge`, sweep::merge_shards): a union of rows, checked.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "table/table.h"

namespace aovar::table {

// Joins shard tables read from `inputs`: their meta must match except "shard"; rows with the same key
// must be identical (else std::runtime_error "conflicting rows for KEY in A and B"). The result's
// meta is the first's without "shard", plus "merged_from" (the file names); every row's `pareto` is false
// (a shard's front is not the merged table's: the caller marks it, decide::mark_pareto).
// `per_shard`: further meta keys each shard has its own of (not compared, left out of the result).
CostTable merge_tables(const std::vector<std::filesystem::path>& inputs, const std::vector<std::string>& per_shard = {});
// The same over tables already read, each with the name errors give it.
CostTable merge_tables(std::vector<std::pair<std::string, CostTable>> tables, const std::vector<std::string>& per_shard = {});

}  // namespace aovar::table
