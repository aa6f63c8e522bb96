// Shards, second pass (issue 34, points 2, 10, 11): a shard count nobody could mean is refused before
// anything is planned per shard; a shard manifest's numbers are whole numbers, not truncated; a complete
// sweep shard pins its rows (count and a hash of their keys), and merge refuses a table with rows removed.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "shard/assign.h"
#include "shard/env.h"
#include "shard/manifest.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
using json = nlohmann::json;

template <class F>
std::string limit_error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ShardLimits, ACountNobodyCouldMeanIsRefusedAtOnce) {
  const auto start = std::chrono::steady_clock::now();
  for (const char* text : {"1/1000000000", "1/10001", "10001/10001", "1/99999999999999999999", "1/2147483648"}) {
    const std::string e = limit_error_of([&] { shard::parse_shard_option(text, {}); });
    EXPECT_NE(e.find("--shard"), std::string::npos) << text << ": " << e;
  }
  EXPECT_EQ(shard::parse_shard_option("1/10000", {}).count, shard::kMaxShards);
  for (const shard::Env& env : {shard::Env{{"AOVAR_SHARD_INDEX", "0"}, {"AOVAR_SHARD_TOTAL", "1000000000"}},
                                shard::Env{{"JOB_COMPLETION_INDEX", "3"}, {"AOVAR_SHARD_TOTAL", "1000000000"}},
                                shard::Env{{"CI_NODE_INDEX", "1"}, {"CI_NODE_TOTAL", "20000"}}}) {
    const std::string e = limit_error_of([&] { shard::parse_shard_option("auto", env); });
    EXPECT_NE(e.find("more than 10000 shards"), std::string::npos) << e;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(ShardLimits, MoreShardsThanUnitsIsRefusedBeforeTheAssignment) {
  std::vector<shard::Unit> units = {{"a", 1, {}}, {"b", 2, {}}, {"c", 3, {}}};
  EXPECT_NO_THROW(shard::assign(units, 3));
  EXPECT_NE(limit_error_of([&] { shard::assign(units, 4); }).find("4 shards for 3 units of work; use at most 3 shards"),
            std::string::npos);
  EXPECT_NE(limit_error_of([&] { shard::assign(units, shard::kMaxShards); }).find("use at most 3"), std::string::npos);
  EXPECT_NE(limit_error_of([&] { shard::assign({}, 2); }).find("2 shards for 0 units"), std::string::npos);
}

json manifest_json() {
  shard::ShardManifest m;
  m.tool = "sweep";
  m.version = "aovar test";
  m.inputs = {{"manifest", "m1"}};
  m.input_hash = shard::hash_inputs(m.inputs);
  m.index = 1;
  m.count = 3;
  m.units = 4;
  m.done = 2;
  m.complete = true;
  m.rows_hash = shard::hash_row_keys({"a", "b"});
  return m.to_json();
}

TEST(ShardLimits, ManifestNumbersAreWholeNumbers) {
  TempDir dir;
  util::write_atomic(dir / "shard.json", manifest_json().dump());
  EXPECT_EQ(shard::read_manifest(dir / "shard.json").index, 1);
  for (const auto& [pointer, value] : std::vector<std::pair<std::string, json>>{
           {"/shard/index", 2.5}, {"/shard/index", 2.0}, {"/shard/count", 3e10}, {"/shard/count", -3},
           {"/units", 4.5}, {"/done", -1}, {"/shard/index", "2"}, {"/rows/count", 2.5}}) {
    json j = manifest_json();
    j[json::json_pointer(pointer)] = value;
    util::write_atomic(dir / "shard.json", j.dump());
    const std::string e = limit_error_of([&] { shard::read_manifest(dir / "shard.json"); });
    EXPECT_NE(e.find("shard.json: "), std::string::npos) << pointer << " " << value << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    if (value.is_number()) { EXPECT_NE(e.find("not a whole number"), std::string::npos) << pointer << " " << value << ": " << e; }
  }
}

TEST(ShardLimits, PinnedRowsMustBeThoseOfTheTable) {
  shard::ShardManifest m = shard::ShardManifest::from_json(manifest_json(), "s2");
  EXPECT_NO_THROW(shard::check_pinned_rows("s2", m, "t.json", {"b", "a"}));  // any order
  EXPECT_NE(limit_error_of([&] { shard::check_pinned_rows("s2", m, "t.json", {"a"}); })
                .find("shard 2/3 (s2): t.json has 1 rows, its shard.json says the shard wrote 2"),
            std::string::npos);
  EXPECT_NE(limit_error_of([&] { shard::check_pinned_rows("s2", m, "t.json", {"a", "c"}); }).find("are not the ones"),
            std::string::npos);
  m.rows_hash.clear();
  EXPECT_NE(limit_error_of([&] { shard::check_pinned_rows("s2", m, "t.json", {"a", "b"}); }).find("pins no row set"),
            std::string::npos);
  m.tool = "stress";  // stress and generate have no table to pin
  EXPECT_NO_THROW(shard::check_pinned_rows("s2", m, "t.json", {"a"}));
}

table::CostRow row(const std::string& variant) {
  table::CostRow r;
  r.variant = variant;
  r.scene = "builtin:atrium";
  r.view = "overview";
  r.backend = "lavapipe";
  r.time_ms = {1, 1, 1, 5};
  return r;
}

// Two shards as a sweep leaves them (shard.json pinned to its cost_table.json); merge joins them, and refuses
// once rows are deleted from one of them, writing nothing.
TEST(ShardLimits, MergeRefusesAShardWithRowsDeleted) {
  TempDir dir;
  for (int k = 0; k < 2; ++k) {
    const auto shard_dir = dir / ("s" + std::to_string(k + 1));
    std::filesystem::create_directories(shard_dir);
    table::CostTable t;
    std::vector<std::string> keys;
    for (int i = 0; i < 5; ++i) {
      t.rows.push_back(row(fmt::format("v{}-{}", k, i)));
      keys.push_back(t.rows.back().key());
    }
    table::write_json(t, shard_dir / "cost_table.json");
    shard::ShardManifest m = shard::ShardManifest::from_json(manifest_json(), "x");
    m.index = k;
    m.count = 2;
    m.done = 5;
    m.rows_hash = shard::hash_row_keys(keys);
    shard::write_manifest(shard_dir, m);
  }
  const std::string args = "merge " + (dir / "merged.json").string() + " " + (dir / "s1").string() + " " + (dir / "s2").string();
  auto ok = run_aovar(args);
  ASSERT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("10 rows from 2 shards"), std::string::npos) << ok.output;
  std::filesystem::remove(dir / "merged.json");

  json t = json::parse(util::read_file(dir / "s2" / "cost_table.json").value());
  t["rows"].erase(t["rows"].begin() + 3);
  t["rows"].erase(t["rows"].begin() + 1);
  util::write_atomic(dir / "s2" / "cost_table.json", t.dump());
  auto refused = run_aovar(args);
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("shard 2/2 (" + util::display_path(dir / "s2") + "): "), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("has 3 rows, its shard.json says the shard wrote 5"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "merged.json"));
}

}  // namespace
}  // namespace aovar::test
