#pragma once
// `aovar merge` of sweep shards: the shard manifests are checked as one set (shard/manifest.h: none missing,
// duplicated, incomplete or from other inputs), the tables joined (table::merge_tables), and what each shard
// fitted on its own rows (the cost models) refitted on the joined rows, so the result holds the rows one
// unsharded sweep would (times are each shard's own).
#include <filesystem>
#include <string>
#include <vector>

#include "table/table.h"

namespace aovar::sweep {

struct MergeResult {
  table::CostTable table;
  int shards = 0;        // inputs with a shard manifest (0: plain tables, joined as before)
  std::string balance;   // shard::balance_summary of the shards, empty without manifests
};

// Each input is a sweep's output folder or its cost_table.json; a folder's shard.json is next to the table.
// `out`: the merged cost_table.json, whose folder the rows' image paths are made relative to.
// Throws std::runtime_error (one line naming the shard or file).
MergeResult merge_shards(const std::vector<std::filesystem::path>& inputs, const std::filesystem::path& out);

}  // namespace aovar::sweep
