// Numbers are checked in one place (issue 54, cli/limits.h): every floating option finite and in range,
// every whole number at most a stated maximum, all before anything renders; the error is one line naming
// the command that was run and the option. Reproductions 3, 7, 9 (the checks after the fit) and 12, with
// more members of each class.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "test_support.h"

namespace aovar::test {
namespace {

struct OptionRefusal {
  std::string args;     // after `aovar`
  std::string command;  // the subcommand the message must name
  std::string option;   // and the option
};

TEST(OptionLimits, NumbersNobodyCouldMeanAreOneLineUsageErrorsBeforeAnythingRenders) {
  TempDir dir;
  const std::string out = (dir / "out").string();
  const std::string ship = "ship --scene builtin:stairs --size 64x36 --rays 16 --out " + out + " ";
  const std::string sweep = "sweep --scene builtin:stairs --size 64x36 --rays 16 --out " + out + " ";
  const std::vector<OptionRefusal> cases = {
      {ship + "--gpu-window nan", "ship", "--gpu-window"},            // reproduction 3
      {sweep + "--gpu navi21 --gpu-window nan", "sweep", "--gpu-window"},
      {sweep + "--gpu navi21 --gpu-window inf", "sweep", "--gpu-window"},
      {ship + "--rays 2147483647", "ship", "--rays"},                  // reproduction 7
      {"reference --scene builtin:stairs --rays 2147483647 --out " + out, "reference", "--rays"},
      {"calibrate --rays 0 --out " + out + "/c.json", "calibrate", "--rays"},
      {ship + "--race-reps 2147483647", "ship", "--race-reps"},        // reproduction 12
      {ship + "--threads 1000", "ship", "--threads"},
      {"measure --scene builtin:stairs --threads 1000 --out " + out, "measure", "--threads"},
      {"measure --scene builtin:stairs --reps 2147483647 --out " + out, "measure", "--reps"},
      {ship + "--ci-target 0", "ship", "--ci-target"},                 // reproduction 9
      {ship + "--ci-target nan", "ship", "--ci-target"},
      {ship + "--target navi21 --gpu-size 16384x16384", "ship", "--gpu-size"},
      {ship + "--race-margin nan", "ship", "--race-margin"},
      {ship + "--fit-size 0x0", "ship", "--fit-size"},                 // reproduction 13: not "--size"
      {"calibrate --fits-at-once -1 --out " + out + "/c.json", "calibrate", "--fits-at-once"},
      {sweep + "--reps-cap-s inf --reps auto", "sweep", "--reps-cap-s"},
      {sweep + "--min-model-spearman nan", "sweep", "--min-model-spearman"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = run_aovar(c.args);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(r.output.rfind("aovar " + c.command + ": " + c.option, 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_LT(seconds, 15.0) << "refused before anything renders";
  }
}

// An unknown --backend is refused as the options are parsed, by every command that renders: the sanitized
// suite, slow enough to show it, saw measure profile the scene first, and ship wrote OUT/profile/ before failing.
TEST(OptionLimits, AnUnknownBackendIsRefusedBeforeAnythingIsWritten) {
  TempDir dir;
  const std::string out = (dir / "out").string();
  const std::vector<OptionRefusal> cases = {
      {"measure --scene builtin:stairs --backend metal --out " + out, "measure", "--backend"},
      {"sweep --scene builtin:stairs --backend lavapipe,metal --out " + out, "sweep", "--backend"},
      {"ship --scene builtin:stairs --budget-ms 5 --backend metal --out " + out, "ship", "--backend"},
      {"calibrate --backend metal --out " + out + "/c.json", "calibrate", "--backend"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const auto r = run_aovar(c.args);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(r.output.rfind("aovar " + c.command + ": " + c.option + ": unknown backend", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << "wrote before refusing";
  }
}

// The stated maxima themselves are accepted where the option is read (the limits are not off by one).
TEST(OptionLimits, TheStatedMaximaThemselvesPassTheChecks) {
  TempDir dir;
  const auto r = run_aovar("reference --scene builtin:stairs --view overview --size 8x8 --rays 65536 --threads 256 "
                           "--no-cache --out " + (dir / "out").string());
  EXPECT_EQ(r.status, 0) << r.output;
}

}  // namespace
}  // namespace aovar::test
