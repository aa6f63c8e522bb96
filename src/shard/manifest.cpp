// OUT/shard.json and the checks `aovar merge` runs on a set of them.
#include "shard/manifest.h"

#include "util/schema.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "util/fs.h"
#include "util/hash.h"

namespace aovar::shard {
using json = nlohmann::json;

std::string ShardManifest::label() const { return fmt::format("{}/{}", index + 1, count); }

json ShardManifest::to_json() const {
  json j = {{"schema_version", util::kSchemaVersion},
            {"tool", tool},
            {"aovar_version", version},
            {"input_hash", input_hash},
            {"inputs", inputs},
            {"shard", {{"index", index + 1}, {"count", count}, {"convention", convention}}},
            {"units", units},
            {"plan", plan},
            {"done", done},
            {"complete", complete},
            {"wall_s", wall_s}};
  if (!rows_hash.empty()) j["rows"] = {{"count", done}, {"keys_hash", rows_hash}};
  return j;
}

namespace {

// A count or a shard number: a JSON integer that fits an int. nlohmann's get<int>() truncates 2.5 to 2 and
// wraps 2^40: a forged or mistyped shard.json would name another shard.
int whole_number(const json& j, const char* field) {
  if (!j.is_number_integer() || j.get<std::int64_t>() < 0 || j.get<std::int64_t>() > std::numeric_limits<int>::max())
    throw std::runtime_error(fmt::format("'{}' is {}, not a whole number from 0 to {}", field, j.dump(),
                                         std::numeric_limits<int>::max()));
  return j.get<int>();
}

}  // namespace

ShardManifest ShardManifest::from_json(const json& j, const std::string& source) {
  try {
    util::check_schema_version(j.at("schema_version"), source);  // a newer aovar's shard: refused in one line
    ShardManifest m;
    m.tool = j.at("tool").get<std::string>();
    m.version = j.at("aovar_version").get<std::string>();
    m.input_hash = j.at("input_hash").get<std::string>();
    m.inputs = j.at("inputs");
    m.index = whole_number(j.at("shard").at("index"), "shard.index") - 1;
    m.count = whole_number(j.at("shard").at("count"), "shard.count");
    m.convention = j.at("shard").value("convention", "");
    m.units = whole_number(j.at("units"), "units");
    m.plan = j.value("plan", json());
    m.done = whole_number(j.at("done"), "done");
    m.complete = j.at("complete").get<bool>();
    m.wall_s = j.value("wall_s", 0.0);
    if (j.contains("rows")) {
      const json& rows = j.at("rows");
      if (whole_number(rows.at("count"), "rows.count") != m.done)
        throw std::runtime_error(fmt::format("rows.count {} differs from done {}", rows.at("count").dump(), m.done));
      m.rows_hash = rows.at("keys_hash").get<std::string>();
    }
    if (m.count < 1 || m.index < 0 || m.index >= m.count)
      throw std::runtime_error(fmt::format("shard {} is outside 1..{}", m.index + 1, m.count));
    return m;
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not a shard manifest ({}): rerun the shard", source, e.what()));
  } catch (const util::NewerSchema&) {
    throw;  // already one line naming the file
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}: {}: rerun the shard with this aovar", source, e.what()));
  }
}

ShardManifest planned_manifest(const std::string& tool, const std::string& version, const json& inputs,
                               const Assignment& assignment, int index, const std::string& convention,
                               const std::string& costs_from) {
  ShardManifest m;
  m.tool = tool;
  m.version = version;
  m.inputs = inputs;
  m.input_hash = hash_inputs(inputs);
  m.index = index;
  m.count = assignment.count;
  m.convention = convention;
  m.units = assignment.units.at(index);
  m.plan = assignment.to_json();
  m.plan["costs_from"] = costs_from;
  return m;
}

std::string hash_row_keys(std::vector<std::string> keys) {
  std::sort(keys.begin(), keys.end());
  util::Hasher h;
  for (const auto& k : keys) h.add(k).add("\n");
  return h.hex();
}

void check_pinned_rows(const std::string& name, const ShardManifest& m, const std::string& table,
                       const std::vector<std::string>& keys) {
  if (m.tool != "sweep" || !m.complete) return;
  if (m.rows_hash.empty())
    throw std::runtime_error(fmt::format("merge: shard {} ({}): its {} pins no row set (written by an older aovar): "
                                         "rerun the shard with this aovar",
                                         m.label(), name, kManifestFile));
  if (static_cast<std::size_t>(m.done) != keys.size())
    throw std::runtime_error(fmt::format("merge: shard {} ({}): {} has {} rows, its {} says the shard wrote {}: rows "
                                         "were removed or added since; rerun the shard",
                                         m.label(), name, table, keys.size(), kManifestFile, m.done));
  if (hash_row_keys(keys) != m.rows_hash)
    throw std::runtime_error(fmt::format("merge: shard {} ({}): the rows of {} are not the ones its {} pins (same "
                                         "count, other keys): rerun the shard",
                                         m.label(), name, table, kManifestFile));
}

std::string hash_inputs(const json& inputs) { return util::hash_hex(inputs.dump()); }

void write_manifest(const std::filesystem::path& out_dir, const ShardManifest& m) {
  util::write_atomic(out_dir / kManifestFile, m.to_json().dump(1) + "\n");
}

ShardManifest read_manifest(const std::filesystem::path& file) {
  const std::string name = util::display_path(file);
  auto text = util::read_file(file);
  if (!text) throw std::runtime_error(name + ": no shard manifest (was this folder written by a sharded run?)");
  json j;
  try {
    j = json::parse(*text);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(fmt::format("{}: not JSON (byte {}): rerun the shard", name, e.byte));
  }
  return ShardManifest::from_json(j, name);
}

namespace {

// The first input whose hash differs between two manifests (for the message), or "" when none does.
std::string differing_input(const ShardManifest& a, const ShardManifest& b) {
  if (a.tool != b.tool) return "tool";
  if (a.version != b.version) return "aovar_version";
  for (const auto& [k, v] : a.inputs.items())
    if (!b.inputs.contains(k) || b.inputs[k] != v) return k;
  for (const auto& [k, v] : b.inputs.items())
    if (!a.inputs.contains(k)) return k;
  return a.input_hash != b.input_hash ? "input_hash" : "";
}

}  // namespace

void check_shard_set(const std::vector<std::pair<std::string, ShardManifest>>& shards) {
  if (shards.empty()) throw std::runtime_error("merge: no shards given");
  const auto& [first_name, first] = shards.front();
  std::map<int, std::string> by_index;
  for (const auto& [name, m] : shards) {
    if (std::string d = differing_input(first, m); !d.empty() || m.count != first.count)
      throw std::runtime_error(fmt::format("merge: shard {} ({}) is from another run than {} ({}): its {} differs; "
                                           "merge only shards of one command",
                                           m.label(), name, first.label(), first_name,
                                           d.empty() ? "shard count" : "'" + d + "'"));
    if (auto [it, fresh] = by_index.emplace(m.index, name); !fresh)
      throw std::runtime_error(fmt::format("merge: shard {} is given twice ({} and {}): give each shard once",
                                           m.label(), it->second, name));
  }
  for (const auto& [name, m] : shards)
    if (!m.complete)
      throw std::runtime_error(fmt::format("merge: shard {} ({}) is incomplete ({} done when it stopped): rerun it "
                                           "with the same command (it resumes), then merge",
                                           m.label(), name, m.done));
  for (int i = 0; i < first.count; ++i)
    if (!by_index.count(i)) {
      std::vector<std::string> have;
      for (const auto& [k, name] : by_index) have.push_back(fmt::format("{}/{}", k + 1, first.count));
      throw std::runtime_error(fmt::format("merge: shard {}/{} is missing (given: {}): run it, then merge all {}",
                                           i + 1, first.count, fmt::join(have, ", "), first.count));
    }
}

std::string balance_summary(const std::vector<std::pair<std::string, ShardManifest>>& shards) {
  double planned = shards.front().second.plan.is_object() ? shards.front().second.plan.value("max_over_mean", 1.0) : 1.0;
  double sum = 0, lo = 1e300, hi = 0;
  for (const auto& [name, m] : shards) {
    sum += m.wall_s;
    lo = std::min(lo, m.wall_s);
    hi = std::max(hi, m.wall_s);
  }
  double mean = sum / static_cast<double>(shards.size());
  return fmt::format("{} shards: planned max/mean {:.2f}; wall max/mean {:.2f} ({:.1f} s .. {:.1f} s)", shards.size(),
                     planned, mean > 0 ? hi / mean : 1.0, lo, hi);
}

}  // namespace aovar::shard
