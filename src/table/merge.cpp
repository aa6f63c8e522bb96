// `aovar merge`'s join: the rows of shard tables as one table (a union of rows, checked; no decision).
#include "table/merge.h"

#include <fmt/format.h>

#include <map>
#include <stdexcept>

#include "util/fs.h"

namespace aovar::table {

CostTable merge_tables(const std::vector<std::filesystem::path>& inputs, const std::vector<std::string>& per_shard) {
  std::vector<std::pair<std::string, CostTable>> tables;
  for (const auto& in : inputs) tables.emplace_back(util::display_path(in), read_table(in));
  return merge_tables(std::move(tables), per_shard);
}

CostTable merge_tables(std::vector<std::pair<std::string, CostTable>> tables, const std::vector<std::string>& per_shard) {
  if (tables.empty()) throw std::runtime_error("merge: no input tables");
  CostTable out;
  nlohmann::json first_meta;
  std::map<std::string, std::pair<nlohmann::json, std::string>> seen;  // key -> row json, file
  std::vector<std::string> from;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    auto& [name, t] = tables[i];
    // Compared as written: the message names the first key that differs, whatever its type.
    nlohmann::json meta = to_json(t.meta);
    meta.erase("shard");
    meta.erase("reps_reached");  // what each shard's timing reached: its own
    // The same calibration (by hash) read from each machine's own copy: `file` is where, not what.
    if (meta.contains("calibration") && meta["calibration"].is_object()) meta["calibration"].erase("file");
    for (const auto& k : per_shard) meta.erase(k);
    if (i == 0) {
      first_meta = meta;
    } else if (meta != first_meta) {
      std::string field;
      for (const auto& [k, v] : first_meta.items())
        if (!meta.contains(k) || meta[k] != v) { field = k; break; }
      if (field.empty())
        for (const auto& [k, v] : meta.items())
          if (!first_meta.contains(k)) { field = k; break; }
      throw std::runtime_error(fmt::format("merge: {} and {} come from different runs (meta '{}' differs)",
                                           tables[0].first, name, field));
    }
    from.push_back(name);
    for (auto& r : t.rows) {
      r.pareto = false;  // a front of one shard's rows: the caller marks the merged table's (decide::mark_pareto)
      nlohmann::json j = to_json(r);
      auto [it, fresh] = seen.try_emplace(r.key(), j, name);
      if (!fresh) {
        if (it->second.first != j)
          throw std::runtime_error(fmt::format("merge: conflicting rows for {} in {} and {}", r.key(),
                                               it->second.second, name));
        continue;
      }
      out.rows.push_back(std::move(r));
    }
  }
  out.meta = sweep_meta_from_json(first_meta);
  out.meta.merged_from = from;
  return out;
}

}  // namespace aovar::table
