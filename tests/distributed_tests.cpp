// Sweeps past one machine (issue 22), end to end through the CLI and the examples under
// examples/distributed/: a Slurm array of 4 shards (a one-node cluster from scripts/slurm-local, or, where
// Slurm cannot run, the same 4 shards as concurrent local processes with the Slurm environment set) merges to
// the rows of one unsharded sweep; a shard killed with SIGKILL is refused by merge as incomplete, resumes
// from its own rows when resubmitted and then merges to the same rows; merge refuses a missing, a duplicated
// and a foreign shard; and every example parses and uses only the flags these tests run.
// Own executable and ctest label `distributed` (tests/CMakeLists.txt); the examples test is instant, the two
// sweeps take seconds each (tiny frames, 6 variants, one view, 2 reps).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;

// The selection every test here sweeps: 6 variants (a mediump / highp twin pair among them) in 5 units.
const std::string kSelection =
    "--scene builtin:stairs --view closeup --variants alchemy-s04-p0-nrg8-zdep-rst-d16-b*-x1-hp "
    "--variants alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-mp --variants crytek-s04-*-bno-x1-hp --size 48x27 --rays 8 "
    "--reps 2 --warmup 0 --batch 1";
// The aovar flags the examples may use: exactly those the tests below pass them through (kSelection aside,
// which the examples take from AOVAR_SWEEP_ARGS; their default names a --scene).
const std::set<std::string> kExampleFlags = {"--shard", "--cache-dir", "--out", "--table", "--scene"};

fs::path example(const std::string& rel) { return source_dir() / "examples" / "distributed" / rel; }

// The rows as one process and a merge must both give them: without times, the Pareto flags they decide and
// the image paths (relative to each table's folder); sorted, as merge orders rows by shard.
std::string rows_of(const fs::path& table) {
  json t = json::parse(util::read_file(table).value_or("{}"));
  std::vector<std::string> rows;
  for (json row : t.value("rows", json::array())) {
    for (const char* k :
         {"time_ms", "gbuffer_ms", "rel_time", "rel_time_ci", "rel_time_median", "rounds", "pareto", "images"})
      row.erase(k);
    rows.push_back(row.dump());
  }
  std::sort(rows.begin(), rows.end());
  std::string text;
  for (const auto& r : rows) text += r + "\n";
  return text;
}

// Every image a merged table names exists, relative to the merged table's folder.
void expect_images_exist(const fs::path& table) {
  json t = json::parse(util::read_file(table).value_or("{}"));
  int images = 0;
  for (const auto& row : t.at("rows"))
    for (const auto& image : row.value("images", json::array())) {
      ++images;
      EXPECT_TRUE(fs::exists(table.parent_path() / image.get<std::string>())) << image;
    }
  EXPECT_GT(images, 0);
}

std::string sweep_args(const fs::path& cache, const fs::path& out) {
  return "sweep " + kSelection + " --cache-dir " + cache.string() + " --out " + out.string();
}

// scripts/slurm-local's cluster, stopped (by the pids it recorded) when the test ends.
struct LocalSlurm {
  ScopedEnv conf;  // SLURM_CONF while the cluster is up
  fs::path dir;
  bool up = false;
  std::string why_not;
  explicit LocalSlurm(const fs::path& d) : dir(d) {
    auto r = run_command((source_dir() / "scripts" / "slurm-local").string() + " start " + dir.string());
    up = r.status == 0;
    if (up) conf.set("SLURM_CONF", (dir / "slurm.conf").c_str());
    else why_not = r.output;
  }
  ~LocalSlurm() { run_command((source_dir() / "scripts" / "slurm-local").string() + " stop " + dir.string()); }
};

TEST(Distributed, SlurmArrayOfFourMergesToTheRowsOfOneProcess) {
  TempDir dir;
  const fs::path shards = dir / "shards";
  auto whole = run_aovar(sweep_args(shards / "cache", dir / "whole"));  // the compile cache the shards use
  ASSERT_EQ(whole.status, 0) << whole.output;
  // The example batch scripts, as a user submits them (their environment: AOVAR, AOVAR_OUT, AOVAR_SWEEP_ARGS).
  ScopedEnv env;
  env.set("AOVAR", AOVAR_EXE);
  env.set("AOVAR_OUT", shards.c_str());
  env.set("AOVAR_SWEEP_ARGS", kSelection.c_str());
  const std::string sweep = example("slurm/sweep.sbatch").string(), merge = example("slurm/merge.sbatch").string();
  LocalSlurm slurm(dir / "slurm");
  CommandResult array, merged;
  if (slurm.up) {
    // --cpus-per-task=1: two tasks at a time on this 2-core node instead of the script's one.
    array = run_command("sbatch --wait --array=0-3 --cpus-per-task=1 --output=" + (dir / "task-%a.log").string() + " " + sweep);
    for (const char* log : {"task-0.log", "task-1.log", "task-2.log", "task-3.log"})
      array.output += "\n--- " + std::string(log) + ":\n" + util::read_file(dir / log).value_or("(none)");
  } else {
    std::cout << "note: Slurm cannot run here, so the 4 shards run as concurrent local processes with "
                 "SLURM_ARRAY_TASK_ID/COUNT/MIN set, as the array would (the documented stand-in). Why: "
              << slurm.why_not << std::endl;
    std::string cmd = "pids=; for i in 0 1 2 3; do SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=4 SLURM_ARRAY_TASK_MIN=0 "
                      "bash " + sweep + " > " + (dir / "task-").string() + "$i.log 2>&1 & pids=\"$pids $!\"; done; rc=0; "
                      "for p in $pids; do wait $p || rc=1; done; cat " + (dir / "task-").string() + "*.log; exit $rc";
    array = run_command(cmd);
  }
  // The merge job's script, run here: through sbatch --wait it would only add a scheduler poll (10 s).
  merged = run_command("bash " + merge);
  ASSERT_EQ(array.status, 0) << array.output;
  ASSERT_EQ(merged.status, 0) << merged.output << array.output;
  for (int i = 0; i < 4; ++i) {
    json m = json::parse(util::read_file(shards / ("shard-" + std::to_string(i)) / "shard.json").value_or("{}"));
    EXPECT_EQ(m.at("shard").at("index"), i + 1);
    EXPECT_EQ(m.at("shard").at("convention"), "Slurm array");
    EXPECT_TRUE(m.at("complete").get<bool>());
  }
  EXPECT_EQ(rows_of(shards / "cost_table.json"), rows_of(dir / "whole" / "cost_table.json"));
  expect_images_exist(shards / "cost_table.json");
  EXPECT_TRUE(fs::exists(shards / "report.html"));
  EXPECT_EQ(merged.output.find("not embedded"), std::string::npos) << "the report finds the shards' images: " << merged.output;
}

TEST(Distributed, AKilledShardIsRefusedThenResumesAndMerges) {
  TempDir dir;
  const fs::path cache = dir / "cache";
  auto whole = run_aovar(sweep_args(cache, dir / "whole"));
  ASSERT_EQ(whole.status, 0) << whole.output;
  auto one = run_aovar(sweep_args(cache, dir / "s1") + " --shard 1/2");
  ASSERT_EQ(one.status, 0) << one.output;
  const std::string two_args = sweep_args(cache, dir / "s2") + " --shard 2/2";
  ASSERT_TRUE(kill_after_checkpoint(two_args, dir / "s2" / "measure" / "builtin_stairs" / "measure.json", dir / "s2.log"))
      << "shard 2/2 finished before its first checkpoint could be killed: " << util::read_file(dir / "s2.log").value_or("");
  const fs::path merged = dir / "merged" / "cost_table.json";
  auto incomplete = run_aovar("merge " + merged.string() + " " + (dir / "s1").string() + " " + (dir / "s2").string());
  EXPECT_NE(incomplete.status, 0);
  EXPECT_NE(incomplete.output.find("shard 2/2 (" + util::display_path(dir / "s2") + ") is incomplete"), std::string::npos)
      << incomplete.output;
  // Resubmitted (as Slurm's requeue or a replaced Kubernetes pod would): it resumes from its own rows.
  auto resumed = run_aovar(two_args);
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(resumed.output, m, std::regex(R"((\d+) measured, (\d+) reused)"))) << resumed.output;
  EXPECT_GE(std::stoi(m[2]), 1) << "the resumed shard measured everything again: " << resumed.output;
  auto ok = run_aovar("merge " + merged.string() + " " + (dir / "s1").string() + " " + (dir / "s2").string());
  ASSERT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("balance: 2 shards"), std::string::npos) << ok.output;
  EXPECT_EQ(rows_of(merged), rows_of(dir / "whole" / "cost_table.json"));

  // What merge refuses, each with a line naming the shard.
  auto missing = run_aovar("merge " + merged.string() + " " + (dir / "s1").string());
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("shard 2/2 is missing"), std::string::npos) << missing.output;
  fs::copy(dir / "s2", dir / "s2-copy", fs::copy_options::recursive);
  auto twice = run_aovar("merge " + merged.string() + " " + (dir / "s1").string() + " " + (dir / "s2").string() + " " +
                         (dir / "s2-copy").string());
  EXPECT_NE(twice.status, 0);
  EXPECT_NE(twice.output.find("shard 2/2 is given twice"), std::string::npos) << twice.output;
  auto other = run_aovar(sweep_args(cache, dir / "s2-other") + " --shard 2/2 --threads 1");  // other inputs
  ASSERT_EQ(other.status, 0) << other.output;
  auto foreign = run_aovar("merge " + merged.string() + " " + (dir / "s1").string() + " " + (dir / "s2-other").string());
  EXPECT_NE(foreign.status, 0);
  EXPECT_NE(foreign.output.find("shard 2/2 (" + util::display_path(dir / "s2-other") + ") is from another run"),
            std::string::npos)
      << foreign.output;
  for (const auto* r : {&incomplete, &missing, &twice, &foreign})
    EXPECT_EQ(std::count(r->output.begin(), r->output.end(), '\n'), 1) << "one line: " << r->output;
}

TEST(Distributed, ShardTimesBalanceByAnEarlierTablesTimes) {
  TempDir dir;
  const fs::path cache = dir / "cache";
  auto whole = run_aovar(sweep_args(cache, dir / "whole"));
  ASSERT_EQ(whole.status, 0) << whole.output;
  auto timed = run_aovar(sweep_args(cache, dir / "s1") + " --shard 1/2 --shard-times " + (dir / "whole" / "cost_table.json").string());
  ASSERT_EQ(timed.status, 0) << timed.output;
  const json plan = read_json(dir / "s1" / "shard.json").at("plan");
  EXPECT_NE(plan.at("costs_from").get<std::string>().find("(5 of 5 units"), std::string::npos) << plan.dump();
  EXPECT_NE(timed.output.find("# shard 1/2: "), std::string::npos) << timed.output;
  // A table that shares no variant with the selection cannot balance anything: refused, one line.
  auto other = run_aovar("sweep --scene builtin:stairs --view closeup --variants gtao-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp "
                         "--size 48x27 --rays 8 --reps 2 --warmup 0 --cache-dir " + cache.string() + " --out " +
                         (dir / "other").string());
  ASSERT_EQ(other.status, 0) << other.output;
  auto refused = run_aovar(sweep_args(cache, dir / "s2") + " --shard 2/2 --shard-times " + (dir / "other" / "cost_table.json").string());
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.output.find("none of its measured rows is a selected variant"), std::string::npos) << refused.output;
  EXPECT_EQ(std::count(refused.output.begin(), refused.output.end(), '\n'), 1) << refused.output;
}

TEST(Distributed, StressShardsSplitTheCasesAndTogetherGiveEveryCheck) {
  TempDir dir;
  // scale-0.01 is compared with baseline: the two stay in one shard.
  const std::string args = "stress --variants alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp --case baseline --case scale-0.01 "
                           "--case far-inf --case grazing-0.5deg --size 32x18 --cache-dir " + (dir / "cache").string();
  auto whole = run_aovar(args + " --out " + (dir / "whole").string());
  ASSERT_EQ(whole.status, 0) << whole.output;
  std::multiset<std::string> checks;
  for (int k = 1; k <= 2; ++k) {
    const fs::path out = dir / ("s" + std::to_string(k));
    // GitLab's convention (1-based), as a `parallel: 2` job would see it.
    auto shard = run_command("CI_NODE_INDEX=" + std::to_string(k) + " CI_NODE_TOTAL=2 " + std::string(AOVAR_EXE) + " " + args +
                             " --shard auto --out " + out.string());
    ASSERT_EQ(shard.status, 0) << shard.output;
    EXPECT_NE(shard.output.find("from GitLab CI"), std::string::npos) << shard.output;
    json m = read_json(out / "shard.json");
    EXPECT_EQ(m.at("tool"), "stress");
    EXPECT_TRUE(m.at("complete").get<bool>());
    EXPECT_EQ(m.at("units"), k) << "1/2: baseline with its scaled copy (cost 2); 2/2: far-inf and grazing (1 each)";
    const json shard_checks = read_json(out / "stress.json").at("checks");
    for (const auto& c : shard_checks) checks.insert(c.dump());
    EXPECT_EQ(m.at("done").get<std::size_t>(), shard_checks.size());
  }
  std::multiset<std::string> expected;
  const json whole_checks = read_json(dir / "whole" / "stress.json").at("checks");
  for (const auto& c : whole_checks) expected.insert(c.dump());
  EXPECT_EQ(checks, expected);
  EXPECT_EQ(expected.size(), 4u);
}

TEST(Distributed, GenerateShardsCompileDisjointVariantsThatTogetherAreTheSelection) {
  TempDir dir;
  const std::string args = "generate --variants alchemy-s04-p0-nrg8-zdep-rst-*-x1-hp --emit index --cache-dir " +
                           (dir / "cache").string();
  auto whole = run_aovar(args + " --out " + (dir / "whole").string());
  ASSERT_EQ(whole.status, 0) << whole.output;
  auto keys = [](const fs::path& index) {
    std::vector<std::string> out;
    const json variants = read_json(index).at("variants");
    for (const auto& v : variants) out.push_back(v.at("key"));
    return out;
  };
  std::multiset<std::string> sharded;
  for (int k = 1; k <= 2; ++k) {
    const fs::path out = dir / ("s" + std::to_string(k));
    auto r = run_aovar(args + " --shard " + std::to_string(k) + "/2 --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (const auto& key : keys(out / "variants.json")) sharded.insert(key);
    EXPECT_TRUE(read_json(out / "shard.json").at("complete").get<bool>());
  }
  const auto all = keys(dir / "whole" / "variants.json");
  EXPECT_GT(all.size(), 2u);
  EXPECT_EQ(sharded, std::multiset<std::string>(all.begin(), all.end()));
}

// The aovar flags of every `aovar`, `$AOVAR` or `build/aovar` command line in a file.
std::set<std::string> aovar_flags(const fs::path& file, int& commands) {
  std::set<std::string> flags;
  const std::string text = util::read_file(file).value_or("");
  std::regex command(R"((?:^|[\s"'(&;])(?:\$AOVAR"?|build/aovar|aovar) (sweep|merge|report)([^\n]*(?:\\\n[^\n]*)*))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), command); it != std::sregex_iterator(); ++it) {
    ++commands;
    const std::string line = (*it)[2];
    std::regex flag(R"((--[a-z][a-z-]*)(?:\s+(\S+))?)");
    for (auto f = std::sregex_iterator(line.begin(), line.end(), flag); f != std::sregex_iterator(); ++f) {
      flags.insert((*f)[1]);
      if ((*f)[1] == "--shard") { EXPECT_EQ((*f)[2], "auto") << file << ": the examples shard with --shard auto"; }
    }
  }
  return flags;
}

TEST(Distributed, ExamplesParseAndUseOnlyTheTestedFlags) {
  // YAML: parsed with PyYAML (python3-yaml, scripts/deps), and the shape each engine needs checked.
  const std::string checks = R"PY(
import sys, yaml
def docs(p): return list(yaml.safe_load_all(open(p)))
gh = docs(sys.argv[1])[0]
sweep, merge = gh["jobs"]["sweep"], gh["jobs"]["merge"]
assert sweep["env"]["AOVAR_SHARD_INDEX"] == "${{ strategy.job-index }}", "GitHub: AOVAR_SHARD_INDEX"
assert sweep["env"]["AOVAR_SHARD_TOTAL"] == "${{ strategy.job-total }}", "GitHub: AOVAR_SHARD_TOTAL"
assert len(sweep["strategy"]["matrix"]["shard"]) > 1, "GitHub: matrix"
assert any("upload-artifact" in s.get("uses", "") for s in sweep["steps"]), "GitHub: per-shard artifacts"
assert merge["needs"] == "sweep" and any("download-artifact" in s.get("uses", "") for s in merge["steps"])
assert any("upload-artifact" in s.get("uses", "") for s in merge["steps"]), "GitHub: report upload"
gl = docs(sys.argv[2])[0]
assert gl["sweep"]["parallel"] > 1 and gl["merge"]["needs"] == ["sweep"], "GitLab: parallel and needs"
k8s = docs(sys.argv[3]); job = [d for d in k8s if d["kind"] == "Job"][0]
assert job["spec"]["completionMode"] == "Indexed", "Kubernetes: Indexed"
env = {e["name"]: e["value"] for e in job["spec"]["template"]["spec"]["containers"][0]["env"]}
assert int(env["AOVAR_SHARD_TOTAL"]) == job["spec"]["completions"], "Kubernetes: AOVAR_SHARD_TOTAL = completions"
claim = [d for d in k8s if d["kind"] == "PersistentVolumeClaim"][0]["metadata"]["name"]
merge_job = docs(sys.argv[4])[0]
for j in (job, merge_job):
    assert j["spec"]["template"]["spec"]["volumes"][0]["persistentVolumeClaim"]["claimName"] == claim, "shared volume"
print("ok")
)PY";
  TempDir dir;
  util::write_atomic(dir / "check.py", checks);
  auto yaml = run_command("python3 " + (dir / "check.py").string() + " " +
                    example("github-actions.yml").string() + " " + example("gitlab-ci.yml").string() + " " +
                    example("kubernetes/sweep-job.yml").string() + " " + example("kubernetes/merge-job.yml").string());
  EXPECT_EQ(yaml.status, 0) << yaml.output;
  EXPECT_EQ(yaml.output, "ok\n");
  for (const char* script : {"slurm/sweep.sbatch", "slurm/merge.sbatch"}) {
    auto syntax = run_command("bash -n " + example(script).string());
    EXPECT_EQ(syntax.status, 0) << script << ": " << syntax.output;
  }
  for (const char* file : {"github-actions.yml", "gitlab-ci.yml", "kubernetes/sweep-job.yml", "kubernetes/merge-job.yml",
                           "slurm/sweep.sbatch", "slurm/merge.sbatch"}) {
    int commands = 0;
    for (const auto& flag : aovar_flags(example(file), commands))
      EXPECT_TRUE(kExampleFlags.count(flag)) << file << " uses " << flag << ", which no distributed test runs";
    EXPECT_GE(commands, 1) << file << ": no aovar command found";
  }
}

}  // namespace
}  // namespace aovar::test
