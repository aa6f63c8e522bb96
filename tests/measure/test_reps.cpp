// --reps auto (issue 18): the stopping rule on synthetic rounds (no timing: which pipelines go on after a
// round). A real --reps auto measurement and its CLI: test_measure.cpp; its place in the inputs hash:
// test_reuse.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "measure/measure.h"
#include "measure/timing.h"

namespace aovar::test {
namespace {

using measure::AutoReps;
using measure::PipelineTiming;
using measure::Stop;

// A pipeline with these frame times (ms), one per round.
PipelineTiming timed(std::vector<double> total_ms) {
  PipelineTiming t;
  t.total_ms = std::move(total_ms);
  return t;
}

std::vector<double> steady(int rounds, double ms) { return std::vector<double>(static_cast<std::size_t>(rounds), ms); }

// Frame times alternating between ms and ms * (1 + swing): a ratio whose interval stays wide.
std::vector<double> noisy(int rounds, double ms, double swing) {
  std::vector<double> out;
  for (int i = 0; i < rounds; ++i) out.push_back(i % 2 ? ms * (1 + swing) : ms);
  return out;
}

const AutoReps kRule{0.02, 100.0, 200};  // a cap no synthetic pipeline reaches unless a test says so

TEST(Reps, RelativeHalfWidthOfTheRatioInterval) {
  EXPECT_EQ(measure::relative_half_width(steady(10, 1.2)), 0.0);
  EXPECT_TRUE(std::isnan(measure::relative_half_width(steady(5, 1.2)))) << "the sign test needs 6 samples";
  // 10 samples: the 95 % interval is [x_(2), x_(9)], here [1.0, 1.2], over the median (nearest rank) 1.0.
  EXPECT_NEAR(measure::relative_half_width(noisy(10, 1.0, 0.2)), 0.1, 1e-12);
}

TEST(Reps, AQuietPipelineStopsAtTheMinimumRoundsAndTheBaselineWithIt) {
  std::vector<PipelineTiming> p{timed(steady(9, 10)), timed(steady(9, 12))};
  measure::stop_after_round(p, 10, kRule);
  EXPECT_EQ(p[1].stop, Stop::running) << "below the minimum of rounds";
  EXPECT_EQ(p[0].stop, Stop::running);
  p = {timed(steady(10, 10)), timed(steady(10, 12))};
  measure::stop_after_round(p, 10, kRule);
  EXPECT_EQ(p[1].stop, Stop::target);
  EXPECT_EQ(p[0].stop, Stop::target) << "nothing else is timed";
}

TEST(Reps, ANoisyPipelineGoesOnAndKeepsTheBaselineInTheRounds) {
  std::vector<PipelineTiming> p{timed(steady(30, 10)), timed(steady(30, 12)), timed(noisy(30, 11, 0.3))};
  measure::stop_after_round(p, 10, kRule);
  EXPECT_EQ(p[1].stop, Stop::target);
  EXPECT_EQ(p[2].stop, Stop::running);
  EXPECT_EQ(p[0].stop, Stop::running) << "the noisy one's ratios need the baseline in the same rounds";
  // A stopped pipeline is not looked at again: its rounds stop growing while the others' do.
  p[2].total_ms.push_back(11);
  measure::stop_after_round(p, 10, kRule);
  EXPECT_EQ(p[1].stop, Stop::target);
  EXPECT_EQ(p[2].stop, Stop::running);
}

TEST(Reps, TheCapStopsANoisyPipeline) {
  // 20 ms frames: 10 rounds are 0.2 s of its own timed frames.
  std::vector<PipelineTiming> p{timed(steady(10, 10)), timed(noisy(10, 20, 0.3))};
  measure::stop_after_round(p, 10, {0.02, 0.2, 200});
  EXPECT_EQ(p[1].stop, Stop::cap);
  EXPECT_EQ(p[0].stop, Stop::target);
  p = {timed(steady(12, 10)), timed(noisy(12, 1, 0.3))};
  measure::stop_after_round(p, 10, {0.02, 100.0, 12});
  EXPECT_EQ(p[1].stop, Stop::cap) << "the hard maximum of rounds";
  p = {timed(steady(11, 10)), timed(noisy(11, 1, 0.3))};
  measure::stop_after_round(p, 10, {0.02, 100.0, 12});
  EXPECT_EQ(p[1].stop, Stop::running);
}

// The race's retirement (timing.h, Retire): noisy pipelines that no target would stop. One with a more
// accurate pipeline twice as fast in the same rounds stops as dominated; a tie inside the margin, a faster
// one that is less accurate, or an unknown error keep it running; the reference retires others, never itself.
TEST(Reps, ARaceRetiresAPipelineAMoreAccurateOneBeatsBeyondTheMargin) {
  const measure::Retire race{{0.05, 0.04, 0.06, 0.03}, 1.10};
  std::vector<PipelineTiming> p{timed(steady(12, 10)), timed(noisy(12, 10, 0.3)), timed(noisy(12, 20, 0.3)),
                                timed(noisy(12, 10.5, 0.3))};
  measure::stop_after_round(p, 10, kRule, &race);
  EXPECT_EQ(p[2].stop, Stop::dominated) << "2x slower than p[1], which is more accurate";
  EXPECT_EQ(p[1].stop, Stop::running) << "p[3] is more accurate but only 1.05x faster: inside the margin";
  EXPECT_EQ(p[3].stop, Stop::running) << "the most accurate: nothing dominates it";
  EXPECT_EQ(p[0].stop, Stop::running) << "the reference is never retired";

  p = {timed(steady(12, 10)), timed(noisy(12, 10, 0.3)), timed(noisy(12, 20, 0.3))};
  const measure::Retire less_accurate{{0.09, 0.07, 0.06}, 1.10};  // the reference: less accurate too
  measure::stop_after_round(p, 10, kRule, &less_accurate);
  EXPECT_EQ(p[2].stop, Stop::running) << "the faster one has more error: no domination";
  const measure::Retire unknown{{0.09, 0.04, NAN}, 1.10};
  measure::stop_after_round(p, 10, kRule, &unknown);
  EXPECT_EQ(p[2].stop, Stop::running) << "an unknown error is never compared";
  const measure::Retire by_reference{{0.01, 0.07, 0.06}, 1.10};
  p = {timed(steady(12, 10)), timed(noisy(12, 25, 0.3))};
  measure::stop_after_round(p, 10, kRule, &by_reference);
  EXPECT_EQ(p[1].stop, Stop::dominated) << "the reference, more accurate and faster, retires it";
  EXPECT_EQ(p[0].stop, Stop::target) << "nothing else is timed";

  p = {timed(steady(9, 10)), timed(noisy(9, 10, 0.3)), timed(noisy(9, 20, 0.3))};
  measure::stop_after_round(p, 10, kRule, &race);
  EXPECT_EQ(p[2].stop, Stop::running) << "below the minimum of rounds";
}

// The held-out views of ship under --budget-of: the reference is the budget, and a pipeline slower than it
// beyond the margin cannot be chosen, however accurate; one within the margin, or faster, goes on.
TEST(Reps, ABudgetReferenceRetiresWhatIsSlowerThanItBeyondTheMargin) {
  std::vector<PipelineTiming> p{timed(steady(12, 10)), timed(noisy(12, 13, 0.3)), timed(noisy(12, 10.5, 0.3)),
                                timed(noisy(12, 8, 0.3))};
  const measure::Retire budget{{0.09, 0.01, 0.01, NAN}, 1.10, true};
  measure::stop_after_round(p, 10, kRule, &budget);
  EXPECT_EQ(p[1].stop, Stop::dominated) << "1.3x the budget's time, though the most accurate";
  EXPECT_EQ(p[2].stop, Stop::running) << "1.05x: inside the margin";
  EXPECT_EQ(p[3].stop, Stop::running) << "faster than the budget, its error unknown";
  p = {timed(steady(12, 10)), timed(noisy(12, 13, 0.3))};
  const measure::Retire no_budget{{0.09, 0.01}, 1.10};
  measure::stop_after_round(p, 10, kRule, &no_budget);
  EXPECT_EQ(p[1].stop, Stop::running) << "without the budget rule a more accurate one is never retired by time";
}

// The race across batches: a row timed in an earlier batch of the view counts through its interval against
// the reference (every batch times it). A pipeline retires once its own interval's low end is at or above
// that row's high end and that row is more accurate; an overlap, or a less accurate earlier row, keeps it.
TEST(Reps, AMoreAccurateRowOfAnEarlierBatchRetiresWhatItBeatsBeyondTheNoise) {
  const auto run = [](std::vector<measure::EarlierRow> earlier) {
    std::vector<PipelineTiming> p{timed(steady(12, 10)), timed(noisy(12, 20, 0.1))};  // ratio 2.0-2.2
    const measure::Retire race{{0.09, 0.05}, 1.0, false, std::move(earlier)};
    measure::stop_after_round(p, 10, kRule, &race);
    return p[1].stop;
  };
  EXPECT_EQ(run({{0.04, 1.5}}), Stop::dominated) << "[2.0, 2.2] lies above 1.5, and 0.04 < 0.05";
  EXPECT_EQ(run({{0.06, 1.5}}), Stop::running) << "the earlier row is less accurate";
  EXPECT_EQ(run({{0.04, 2.1}}), Stop::running) << "the intervals overlap: not beyond the noise";
  EXPECT_EQ(run({{0.06, 1.5}, {0.04, 1.9}}), Stop::dominated) << "any earlier row that beats it";
  EXPECT_EQ(run({}), Stop::running);
}

TEST(Reps, StopNamesRoundTrip) {
  for (Stop s : {Stop::running, Stop::fixed, Stop::target, Stop::cap, Stop::dominated})
    EXPECT_EQ(measure::stop_from_name(measure::stop_name(s)), s);
  EXPECT_EQ(measure::stop_from_name(""), Stop::fixed) << "rows written before --reps auto";
}

}  // namespace
}  // namespace aovar::test
