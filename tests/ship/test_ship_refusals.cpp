// What ship refuses before anything renders (issue 54): a join that would write into its inputs, a --join
// folder that is no shard's, and a --budget-of that no run could time. Each a one-line usage error, exit 2,
// within seconds (nothing is profiled, fitted or raced), and nothing written into the inputs.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

const char* kRefusalBaseline = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";

// Two folders that look like shard runs (a ship.json each).
void make_fake_shard_folders(const TempDir& dir) {
  for (const char* s : {"s1", "s2"}) write_text(dir / s / "ship.json", "{}\n");
}

void expect_refused_before_the_work(const CommandResult& r, const std::string& part, double seconds) {
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(has_text(r.output, part)) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_LT(seconds, 20.0) << "refused before the work, not after it";
}

CommandResult timed_refusal_run(const std::string& args, double& seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  auto r = run_aovar(args);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// Issue 54, reproduction 5: `ship --join j/s1 j/s2 --out j/s1` overwrote shard s1's screen. The second member:
// an --out inside a shard's folder, and merge into a shard's own table.
TEST(JoinIntoInputs, AnOutputThatIsOrLiesInAnInputIsRefusedAndTheInputsStayAsTheyWere) {
  TempDir dir;
  make_fake_shard_folders(dir);
  for (const fs::path& out : {dir / "s1", dir / "s2" / "joined"}) {
    SCOPED_TRACE(out.string());
    double s = 0;
    const auto r = timed_refusal_run(fmt::format("ship --scene builtin:stairs --budget-of {} --join {} {} --out {}", kRefusalBaseline,
                                     (dir / "s1").string(), (dir / "s2").string(), out.string()), s);
    expect_refused_before_the_work(r, "a join never writes into its inputs", s);
    EXPECT_FALSE(fs::exists(dir / "s1" / "screen"));
    EXPECT_FALSE(fs::exists(dir / "s2" / "joined" / "screen"));
  }
  write_text(dir / "s2" / "cost_table.json", "{}");
  const auto merged = run_aovar(fmt::format("merge {} {} {}", (dir / "s2" / "cost_table.json").string(),
                                            (dir / "s1").string(), (dir / "s2").string()));
  EXPECT_EQ(merged.status, 2) << merged.output;
  EXPECT_TRUE(has_text(merged.output, "merge: the output ")) << merged.output;
  EXPECT_EQ(*util::read_file(dir / "s2" / "cost_table.json"), "{}");
  EXPECT_FALSE(fs::exists(dir / "s2" / ".aovar.lock")) << "refused before the lock";
}

// Issue 54, reproduction 13's first member: a missing folder or a file said "screened other inputs".
TEST(JoinIntoInputs, AJoinOfSomethingThatIsNoShardFolderSaysSo) {
  TempDir dir;
  make_fake_shard_folders(dir);
  for (const fs::path& bad : {dir / "missing", fs::path("/etc/passwd")}) {
    SCOPED_TRACE(bad.string());
    double s = 0;
    const auto r = timed_refusal_run(fmt::format("ship --scene builtin:stairs --budget-of {} --join {} {} --out {}", kRefusalBaseline,
                                     (dir / "s1").string(), bad.string(), (dir / "out").string()), s);
    expect_refused_before_the_work(r, "is not the folder of an `aovar ship --shard k/n` run", s);
  }
}

// Issue 54, reproduction 9: --budget-of a key nobody has, a glob, or a key outside --variants profiled,
// fitted, raced and timed before failing.
TEST(BudgetOfResolved, BeforeAnythingRenders) {
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--budget-of nosuch-key", "is no variant of"},
      {"--budget-of 'alchemy-s08-*'", "is a pattern"},
      {fmt::format("--budget-of {} --variants 'sao-s08-*'", kRefusalBaseline), "is outside --variants"}};
  for (const auto& [args, part] : cases) {
    SCOPED_TRACE(args);
    double s = 0;
    const auto r = timed_refusal_run(fmt::format("ship --scene builtin:stairs {} --rays 16 --size 64x36 --cache-dir {} --out {}",
                                     args, (dir / "cache").string(), (dir / "out").string()), s);
    expect_refused_before_the_work(r, part, s);
    EXPECT_FALSE(fs::exists(dir / "out" / "ship.json"));
  }
}

}  // namespace
}  // namespace aovar::test

namespace aovar::test {
namespace {

// Issue 54, reproduction 10: a truncated OUT/calibration.json blocked the resume of a run, while damaged
// profiles and round tables are recomputed. Now it is fitted again with a warning, as they are; the second
// member: a fit whose values lie outside the manifest's ranges.
TEST(ShipFit, ADamagedFitIsFittedAgainOnResume) {
  TempDir dir;
  const std::string args = fmt::format(
      "ship --scene builtin:atrium --variants 'alchemy-s0[48]-p0-*-zdep-rst-d16-bsep-x1-hp' --budget-of {} "
      "--backend lavapipe --size 64x36 --fit-size 8x8 --evaluations 1 --rays 8 --reps-cap-s 0.1 "
      "--cache-dir {} --out {}",
      kRefusalBaseline, (dir / "cache").string(), (dir / "out").string());
  const auto first = run_aovar(args);
  ASSERT_EQ(first.status, 0) << first.output;
  const fs::path fit = dir / "out" / "calibration.json";
  const std::string whole = *util::read_file(fit);
  nlohmann::json out_of_range = nlohmann::json::parse(whole);
  out_of_range["algorithms"]["alchemy"]["params"]["ao.intensity"] = 1e9;
  for (const std::string& damaged : {whole.substr(0, whole.size() / 2), out_of_range.dump()}) {
    util::write_atomic(fit, damaged);
    const auto again = run_aovar(args);
    EXPECT_EQ(again.status, 0) << again.output;
    EXPECT_TRUE(has_text(again.output, "(a damaged fit: fitting again)")) << again.output;
    EXPECT_NE(*util::read_file(fit), damaged);
  }
}

}  // namespace
}  // namespace aovar::test
