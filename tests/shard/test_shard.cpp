// Sharding as a library (issue 22): --shard auto's conventions (GitHub Actions through AOVAR_SHARD_*, GitLab,
// Slurm, Kubernetes, Bazel) read from an environment map, the cost-balanced assignment, and the checks
// `aovar merge` runs on a set of shard manifests.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>

#include "shard/assign.h"
#include "shard/env.h"
#include "shard/manifest.h"
#include "util/schema.h"
#include "test_support.h"

namespace aovar::test {
namespace {

using shard::Env;

std::string error_of(const Env& env) {
  try {
    shard::shard_from_env(env);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ShardEnv, ExplicitAovarVariablesAreZeroBased) {  // what the GitHub Actions example sets from the matrix
  auto s = shard::shard_from_env({{"AOVAR_SHARD_INDEX", "2"}, {"AOVAR_SHARD_TOTAL", "4"}});
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 4);
  EXPECT_EQ(s.convention, "aovar");
  EXPECT_EQ(s.label(), "3/4");
}

TEST(ShardEnv, GitLabNodeIndexIsOneBased) {
  auto s = shard::shard_from_env({{"CI_NODE_INDEX", "1"}, {"CI_NODE_TOTAL", "3"}});
  EXPECT_EQ(s.index, 0);
  EXPECT_EQ(s.count, 3);
  EXPECT_EQ(s.convention, "GitLab CI");
  EXPECT_NE(s.describe().find("CI_NODE_INDEX=1"), std::string::npos) << s.describe();
}

TEST(ShardEnv, SlurmArrayIndexCountsFromTheArrayMinimumAndStep) {
  auto s = shard::shard_from_env({{"SLURM_ARRAY_TASK_ID", "7"}, {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_MIN", "5"}});
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 4);
  EXPECT_EQ(s.convention, "Slurm array");
  auto stepped = shard::shard_from_env({{"SLURM_ARRAY_TASK_ID", "8"}, {"SLURM_ARRAY_TASK_COUNT", "3"},
                                        {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_STEP", "4"}});
  EXPECT_EQ(stepped.index, 2);
  EXPECT_NE(error_of({{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_COUNT", "3"}, {"SLURM_ARRAY_TASK_MIN", "0"},
                      {"SLURM_ARRAY_TASK_STEP", "2"}})
                .find("not on the array's range"),
            std::string::npos);
}

TEST(ShardEnv, KubernetesCompletionIndexNeedsTheTotalPassedIn) {
  auto s = shard::shard_from_env({{"JOB_COMPLETION_INDEX", "0"}, {"AOVAR_SHARD_TOTAL", "5"}});
  EXPECT_EQ(s.index, 0);
  EXPECT_EQ(s.count, 5);
  EXPECT_EQ(s.convention, "Kubernetes Indexed Job");
  const std::string e = error_of({{"JOB_COMPLETION_INDEX", "1"}});
  EXPECT_NE(e.find("AOVAR_SHARD_TOTAL"), std::string::npos) << e;
}

TEST(ShardEnv, BazelShardsAndItsStatusFile) {
  TempDir dir;
  const auto status = (dir / "status").string();
  auto s = shard::shard_from_env({{"TEST_SHARD_INDEX", "1"}, {"TEST_TOTAL_SHARDS", "2"}, {"TEST_SHARD_STATUS_FILE", status}});
  EXPECT_EQ(s.index, 1);
  EXPECT_EQ(s.count, 2);
  EXPECT_EQ(s.convention, "Bazel");
  EXPECT_EQ(s.status_file, status);
  EXPECT_FALSE(std::filesystem::exists(status));
  shard::touch_status_file(s);
  EXPECT_TRUE(std::filesystem::exists(status));
}

TEST(ShardEnv, NoneDisagreeingPartialOrOutOfRangeIsAOneLineError) {
  for (const auto& [env, expected] : std::vector<std::pair<Env, std::string>>{
           {{}, "no shard in the environment"},
           {{{"CI_NODE_INDEX", "2"}, {"CI_NODE_TOTAL", "4"}, {"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_COUNT", "4"},
             {"SLURM_ARRAY_TASK_MIN", "0"}},
            "GitLab CI says shard 2/4 but Slurm array says 3/4"},
           {{{"CI_NODE_INDEX", "2"}}, "CI_NODE_TOTAL is not"},
           {{{"TEST_SHARD_INDEX", "2"}, {"TEST_TOTAL_SHARDS", "2"}}, "outside 1..2"},
           {{{"CI_NODE_INDEX", "x"}, {"CI_NODE_TOTAL", "2"}}, "not an integer"},
       }) {
    const std::string e = error_of(env);
    EXPECT_NE(e.find(expected), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

TEST(ShardEnv, ConventionsThatAgreeAreFine) {
  auto s = shard::shard_from_env({{"CI_NODE_INDEX", "2"}, {"CI_NODE_TOTAL", "4"}, {"AOVAR_SHARD_INDEX", "1"},
                                  {"AOVAR_SHARD_TOTAL", "4"}});
  EXPECT_EQ(s.label(), "2/4");
  EXPECT_EQ(s.convention, "aovar");  // the explicit one is reported first
}

TEST(ShardEnv, ShardOptionTakesKOfNOrAuto) {
  EXPECT_EQ(shard::parse_shard_option("", {}).count, 1);
  EXPECT_EQ(shard::parse_shard_option("3/4", {}).index, 2);
  EXPECT_EQ(shard::parse_shard_option("auto", {{"CI_NODE_INDEX", "4"}, {"CI_NODE_TOTAL", "4"}}).index, 3);
  for (const char* bad : {"0/4", "5/4", "2/", "a/b", "2/4x"})
    EXPECT_THROW(shard::parse_shard_option(bad, {}), std::runtime_error) << bad;
}

TEST(ShardAssign, BalancesByCostNotCountAndIsDeterministic) {
  // One expensive unit and many cheap ones: by count, the shard with the expensive one would carry 3x the mean.
  std::vector<shard::Unit> units = {{"big", 12, {}}};
  for (int i = 0; i < 12; ++i) units.push_back({"small" + std::to_string(i), 1, {}});
  auto a = shard::assign(units, 2);
  EXPECT_DOUBLE_EQ(a.loads[0], 12);
  EXPECT_DOUBLE_EQ(a.loads[1], 12);
  EXPECT_EQ(a.units[0], 1);  // the big one alone
  EXPECT_DOUBLE_EQ(a.max_over_mean(), 1.0);
  auto reversed = units;
  std::reverse(reversed.begin(), reversed.end());
  auto b = shard::assign(reversed, 2);  // the order units come in does not change who gets what
  for (int k = 0; k < 2; ++k) {
    auto m1 = shard::members_of(units, a, k), m2 = shard::members_of(reversed, b, k);
    EXPECT_EQ(std::set<std::string>(m1.begin(), m1.end()), std::set<std::string>(m2.begin(), m2.end()));
  }
  EXPECT_NE(shard::balance_line(a, 0).find("50.0 %"), std::string::npos) << shard::balance_line(a, 0);
}

TEST(ShardAssign, EveryMemberInExactlyOneShard) {
  std::vector<shard::Unit> units;
  for (int i = 0; i < 30; ++i) units.push_back({"u" + std::to_string(i), 1.0 + (i * 7) % 5, {"u" + std::to_string(i), "twin" + std::to_string(i)}});
  auto a = shard::assign(units, 4);
  std::multiset<std::string> all;
  for (int k = 0; k < 4; ++k)
    for (const auto& m : shard::members_of(units, a, k)) all.insert(m);
  EXPECT_EQ(all.size(), 60u);
  EXPECT_EQ(std::set<std::string>(all.begin(), all.end()).size(), 60u);
  EXPECT_LT(a.max_over_mean(), 1.1);
  EXPECT_THROW(shard::assign({{"a", 1, {}}, {"a", 2, {}}}, 2), std::runtime_error);
  EXPECT_THROW(shard::assign({{"a", 0, {}}}, 2), std::runtime_error);
}

shard::ShardManifest manifest(int index, int count, bool complete = true) {
  shard::ShardManifest m;
  m.tool = "sweep";
  m.version = "aovar test";
  m.inputs = {{"manifest", "m1"}, {"scenes", "s1"}};
  m.input_hash = shard::hash_inputs(m.inputs);
  m.index = index;
  m.count = count;
  m.complete = complete;
  m.done = 3;
  return m;
}

std::string set_error(const std::vector<std::pair<std::string, shard::ShardManifest>>& set) {
  try {
    shard::check_shard_set(set);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ShardManifest, RoundTripsThroughItsFile) {
  TempDir dir;
  auto m = manifest(1, 3, false);
  shard::write_manifest(dir.path(), m);
  auto back = shard::read_manifest(dir / "shard.json");
  EXPECT_EQ(back.to_json(), m.to_json());
  EXPECT_EQ(back.to_json().at("schema_version"), util::kSchemaVersion);
  EXPECT_EQ(back.label(), "2/3");
}

TEST(ShardManifest, AFullSetPasses) {
  EXPECT_EQ(set_error({{"a", manifest(0, 2)}, {"b", manifest(1, 2)}}), "");
}

TEST(ShardManifest, RefusesAShardOfOtherInputs) {
  auto other = manifest(1, 2);
  other.inputs["scenes"] = "s2";
  other.input_hash = shard::hash_inputs(other.inputs);
  const std::string e = set_error({{"a", manifest(0, 2)}, {"b", other}});
  EXPECT_NE(e.find("shard 2/2 (b) is from another run"), std::string::npos) << e;
  EXPECT_NE(e.find("'scenes'"), std::string::npos) << e;
}

TEST(ShardManifest, RefusesAMissingShard) {
  const std::string e = set_error({{"a", manifest(0, 3)}, {"c", manifest(2, 3)}});
  EXPECT_NE(e.find("shard 2/3 is missing"), std::string::npos) << e;
}

TEST(ShardManifest, RefusesADuplicateShard) {
  const std::string e = set_error({{"a", manifest(0, 2)}, {"b", manifest(1, 2)}, {"b2", manifest(1, 2)}});
  EXPECT_NE(e.find("shard 2/2 is given twice (b and b2)"), std::string::npos) << e;
}

TEST(ShardManifest, RefusesAnIncompleteShard) {
  const std::string e = set_error({{"a", manifest(0, 2)}, {"b", manifest(1, 2, false)}});
  EXPECT_NE(e.find("shard 2/2 (b) is incomplete"), std::string::npos) << e;
}

}  // namespace
}  // namespace aovar::test
