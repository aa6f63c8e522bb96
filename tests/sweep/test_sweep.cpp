// aovar sweep: a killed sweep resumes to the same table as an uninterrupted one, shards split the variants
// without overlap and `aovar merge` joins them back.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <chrono>
#include <set>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include "model_verdicts.h"
#include "table/table.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const std::string kVariants =
    " --size 96x54 --reps 2 --rays 32 --batch 2 --variants 'alchemy-s*-p0-nrgb8-zdep-rst-d32-bsep-x1-hp'"
    " --variants 'gtao-s0[48]-p0-nrgb8-zdep-rst-d32-bsep-x1-hp'";
const std::string kArgs = "sweep --scene builtin:stairs --view overview --view closeup" + kVariants;

// Rows by key with what does not depend on timing noise: the error and the health.
std::map<std::string, std::pair<double, long>> deterministic(const table::CostTable& t) {
  std::map<std::string, std::pair<double, long>> out;
  for (const auto& r : t.rows) out[r.key()] = {r.error ? r.error->rmse : -1.0, r.health.nan + r.health.inf};
  return out;
}

// --predict where some group has no predictive model: a non-zero exit with one line naming such a group and
// what to do, and the table left as it was (no predicted rows written).
void expect_predict_refused(const CommandResult& r, const std::set<std::string>& refused, const std::filesystem::path& table_file,
                            std::size_t rows_before) {
  EXPECT_NE(r.status, 0) << r.output;
  const std::string head = "sweep --predict: no predictive cost model for ";
  const auto at = r.output.find(head);
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::string line = r.output.substr(at, r.output.find('\n', at) - at);
  const std::string group = line.substr(head.size(), line.find(' ', head.size()) - head.size());
  EXPECT_TRUE(refused.count(group)) << group << " has a predictive model:\n" << r.output;
  EXPECT_NE(line.find(" (best: "), std::string::npos) << line;
  EXPECT_TRUE(line.ends_with("); measure these variants or lower --min-model-spearman")) << line;
  auto t = table::read_table(table_file);
  EXPECT_EQ(t.rows.size(), rows_before);
  for (const auto& row : t.rows) EXPECT_FALSE(row.predicted) << row.variant;
}

TEST(Sweep, KilledSweepResumesToTheUninterruptedTable) {
  TempDir dir;
  auto full = run_aovar(kArgs + " --out " + (dir / "full").string());
  ASSERT_EQ(full.status, 0) << full.output;
  auto reference = table::read_table(dir / "full" / "cost_table.json");
  ASSERT_EQ(reference.rows.size(), 2u * 9u) << "9 variants x 2 views";
  // Every row carries its static cost: Alchemy's AO pass reads N + 1 depth texels and 1 normal.
  for (const auto& row : reference.rows) {
    ASSERT_TRUE(row.static_cost) << row.variant;
    if (row.variant.rfind("alchemy-", 0) != 0) continue;
    int samples = std::stoi(row.axes.at("samples"));
    EXPECT_EQ(row.static_cost->ao.fetches.depth, samples + 1) << row.variant;
    EXPECT_EQ(row.static_cost->ao.fetches.normal, 1) << row.variant;
  }
  EXPECT_EQ(reference.meta.cost_models.value_or(std::vector<table::ModelFit>{}).size(), 4u)
      << "compact and weighted-class models per view (9 rows each, too few for the full one)";

  // Start the same sweep elsewhere and kill it hard once its first batch is on disk.
  const auto out = dir / "killed";
  std::string cmd = std::string(AOVAR_EXE) + " " + kArgs + " --out " + out.string() + " >/dev/null 2>&1";
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setpgid(0, 0);
    execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  auto measure_json = out / "measure" / "builtin_stairs" / "measure.json";
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!std::filesystem::exists(measure_json) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(-pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(std::filesystem::exists(measure_json)) << "the first batch never reached the disk";
  EXPECT_FALSE(std::filesystem::exists(out / "cost_table.json")) << "killed before the end: no table yet";

  auto resumed = run_aovar(kArgs + " --out " + out.string());
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("reused"), std::string::npos);
  EXPECT_EQ(resumed.output.find(" 0 reused"), std::string::npos) << "the killed run's rows must be reused:\n" << resumed.output;
  auto table = table::read_table(out / "cost_table.json");
  EXPECT_EQ(deterministic(table), deterministic(reference));

  // A second run measures nothing; asked to predict the progressive forms too, it adds one predicted row
  // per view for each Alchemy sample count (the measured non-progressive ones the glob also matches are
  // not repeated).
  std::set<std::string> alchemy;
  for (const auto& row : reference.rows)
    if (row.variant.rfind("alchemy-", 0) == 0) alchemy.insert(row.variant);
  auto again = run_aovar(kArgs + " --predict 'alchemy-s*-p[01]-nrgb8-zdep-rst-d32-bsep-x1-hp' --out " + out.string());
  // The same rows refit to the same models: the resumed table's verdicts say whether --predict may use them
  // (9 rows of 96x54 timings are often noise: then it must refuse).
  if (const auto refused = unpredictable_groups(table::to_json(table.meta.cost_models.value_or(std::vector<table::ModelFit>{}))); !refused.empty())
    return expect_predict_refused(again, refused, out / "cost_table.json", table.rows.size());
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("(0 measured"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find(" " + std::to_string(2 * alchemy.size()) + " predicted"), std::string::npos) << again.output;
  auto with_predictions = table::read_table(out / "cost_table.json");
  ASSERT_EQ(with_predictions.rows.size(), reference.rows.size() + 2 * alchemy.size());
  std::set<std::string> predicted_variants;
  for (const auto& row : with_predictions.rows) {
    if (!row.predicted) continue;
    predicted_variants.insert(row.variant);
    EXPECT_EQ(row.axes.at("progressive"), "true") << row.variant;
    EXPECT_FALSE(row.error) << "a predicted row has no measured error";
    EXPECT_FALSE(row.pareto);
    EXPECT_EQ(row.time_ms.n, 0);
    EXPECT_TRUE(std::isfinite(row.time_ms.min)) << row.variant;
    ASSERT_TRUE(row.static_cost) << row.variant;
    EXPECT_GT(row.static_cost->weighted_ao.alu, 0) << row.variant;
  }
  EXPECT_EQ(predicted_variants.size(), alchemy.size());
  EXPECT_NE(table::to_markdown(with_predictions).find("(predicted)"), std::string::npos);
}

// --own-gbuffers (a G-buffer per variant, as before issue 55) changes what a row's time includes, never its
// error: variants of four G-buffer formats, each sweep in its own folder.
TEST(Sweep, OwnGbuffersGiveTheSameErrorsAsSharedOnes) {
  TempDir dir;
  const std::string args = "sweep --scene builtin:stairs --view overview --size 96x54 --reps 2 --rays 32 --no-prune"
                           " --variants 'alchemy-s04-p0-nrg*-z*-rst-d32-bsep-x1-hp'";
  auto shared = run_aovar(args + " --out " + (dir / "shared").string());
  ASSERT_EQ(shared.status, 0) << shared.output;
  auto own = run_aovar(args + " --own-gbuffers --out " + (dir / "own").string());
  ASSERT_EQ(own.status, 0) << own.output;
  const auto a = deterministic(table::read_table(dir / "shared" / "cost_table.json"));
  ASSERT_EQ(a.size(), 4u) << "rg8 and rgb8 normals, position and depth";
  EXPECT_EQ(a, deterministic(table::read_table(dir / "own" / "cost_table.json")));
}

TEST(Sweep, ShardsSplitTheVariantsWithoutOverlap) {
  TempDir dir;
  std::set<std::string> seen;
  std::size_t rows = 0;
  for (int k = 1; k <= 3; ++k) {
    // --no-prune: the overview alone (96x54) drops 32 samples (more taps than its radius disk has pixels).
    auto r = run_aovar("sweep --scene builtin:stairs --view overview --no-prune" + kVariants + " --shard " + std::to_string(k) + "/3 --out " +
                       (dir / ("s" + std::to_string(k))).string());
    ASSERT_EQ(r.status, 0) << r.output;
    if (!std::filesystem::exists(dir / ("s" + std::to_string(k)) / "cost_table.json")) continue;
    auto t = table::read_table(dir / ("s" + std::to_string(k)) / "cost_table.json");
    for (const auto& row : t.rows) EXPECT_TRUE(seen.insert(row.key()).second) << row.key() << " in two shards";
    rows += t.rows.size();
  }
  EXPECT_EQ(rows, 9u) << "every variant in exactly one shard (overview only)";
  auto bad = run_aovar(kArgs + " --shard 4/3 --out " + (dir / "bad").string());
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("--shard"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace aovar::test
