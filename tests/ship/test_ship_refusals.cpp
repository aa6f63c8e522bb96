// What ship refuses before anything renders (issue 54): a join that would write into its inputs, a --join
// folder that is no shard's, and a --budget-of that no run could time. Each a one-line usage error, exit 2,
// within seconds (nothing is profiled, fitted or raced), and nothing written into the inputs.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "ship/shards.h"
#include "test_support.h"
#include "util/schema.h"
#include "variants/manifest.h"
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
// profiles and round tables are recomputed. Now it is fitted again with a warning, as they are; the other
// members: a fit whose values lie outside the manifest's ranges, one edited within them (ship.json records its
// checksum), and an edited profile.json (it carries its own).
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
  nlohmann::json out_of_range = nlohmann::json::parse(whole), in_range = out_of_range;
  out_of_range["algorithms"]["alchemy"]["params"]["ao.intensity"] = 1e9;
  // Issue 54, one verified layer: an edit that keeps the fit in range and parseable was trusted and changed
  // the answer. ship.json records the fit's checksum: it is fitted again, to the fit of the first run.
  in_range["algorithms"]["alchemy"]["params"]["ao.intensity"] =
      in_range["algorithms"]["alchemy"]["params"]["ao.intensity"].get<double>() * 0.99;
  for (const std::string& damaged : {whole.substr(0, whole.size() / 2), out_of_range.dump(), in_range.dump(1) + "\n"}) {
    util::write_atomic(fit, damaged);
    const auto again = run_aovar(args);
    EXPECT_EQ(again.status, 0) << again.output;
    EXPECT_TRUE(has_text(again.output, "(a damaged fit: fitting again)")) << again.output;
    EXPECT_EQ(*util::read_file(fit), whole) << "the fit is deterministic: fitted again, the first run's";
  }
  // OUT/profile/profile.json likewise carries a checksum: a changed number is profiled again, to the same profile.
  const fs::path profile = dir / "out" / "profile" / "profile.json";
  const std::string profiled = *util::read_file(profile);
  nlohmann::json edited = nlohmann::json::parse(profiled);
  edited["radius"] = edited["radius"].get<double>() * 2;
  nlohmann::json earlier = nlohmann::json::parse(profiled);
  earlier.erase("checksum");  // as an earlier aovar wrote it
  const std::pair<nlohmann::json, std::string> profiles[] = {{edited, "content that does not match its checksum"},
                                                              {earlier, "no checksum (a profile of an earlier aovar)"}};
  for (const auto& [damaged, why] : profiles) {
    util::write_atomic(profile, damaged.dump(1) + "\n");
    const auto again = run_aovar(args);
    EXPECT_EQ(again.status, 0) << again.output;
    EXPECT_TRUE(has_text(again.output, "profile.json: " + why + " (a damaged profile: profiling again)")) << again.output;
    EXPECT_EQ(*util::read_file(profile), profiled);
  }
}

// Issue 54, reproduction 10's first half: a join copied a shard's out-of-range calibration into its own --out,
// where it stuck. A join adopts only a shard fit that is whole (its text the one the shard's ship.json records)
// and within the manifest's ranges; the second member: a shard fit edited after the shard ran.
TEST(ShipFit, AJoinAdoptsOnlyAWholeInRangeShardFit) {
  TempDir dir;
  const auto manifest = variants::load_manifest(source_dir() / "shader_src" / "aovar.toml");
  auto fit_text = [](double intensity) {
    return fmt::format(R"({{"schema_version": {}, "algorithms": {{"alchemy": {{"params": {{"ao.intensity": {}}}}}}}}})",
                       util::kSchemaVersion, intensity) + "\n";
  };
  const std::string inputs = "the fit inputs";
  auto shard = [&](const std::string& name, const std::string& text) {
    write_text(dir / name / "calibration.json", text);
    ship::record_fit(dir / name, inputs);
    return dir / name;
  };
  const fs::path out_of_range = shard("s1", fit_text(1e9));
  const fs::path edited = shard("s2", fit_text(0.5));
  write_text(edited / "calibration.json", fit_text(0.6));
  fs::create_directories(dir / "out");
  const std::string refused =
      thrown_message([&] { ship::adopt_shard_fit({out_of_range, edited}, inputs, dir / "out", manifest); });
  EXPECT_TRUE(has_text(refused, "holds a usable fit of this run's inputs")) << refused;
  EXPECT_TRUE(is_one_line(refused)) << refused;
  EXPECT_FALSE(fs::exists(dir / "out" / "calibration.json")) << "nothing adopted";
  EXPECT_TRUE(has_text(ship::fit_problem(edited, inputs), "does not match the checksum"));

  const fs::path whole = shard("s3", fit_text(0.5));
  ship::adopt_shard_fit({out_of_range, edited, whole}, inputs, dir / "out", manifest);
  EXPECT_EQ(util::read_file(dir / "out" / "calibration.json"), fit_text(0.5));
  EXPECT_EQ(ship::fit_problem(dir / "out", inputs), "") << "adopted with its record";
  EXPECT_EQ(ship::fit_problem(dir / "out", "other inputs"), "a fit of other inputs");
}

}  // namespace
}  // namespace aovar::test
