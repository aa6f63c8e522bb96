// Timing assertions, in their own executable so ctest runs them alone (RUN_SERIAL): another test on the
// same cores would make any cost comparison meaningless.
#include <gtest/gtest.h>

#include <algorithm>

#include "measure/measure.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const std::vector<std::string> kBackends = {"lavapipe", "osmesa"};

TEST(Measure, MoreSamplesNeverCostLess) {
  measure::MeasureOptions o;
  o.manifest = source_dir() / "shader_src" / "aovar.toml";
  o.globs = {"alchemy-s*-p0-nrg8-zdep-rst-d16-bno-x1-hp"};
  o.reference = "alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp";
  o.backends = kBackends;
  o.size = {320, 180};
  o.reps = 7;
  o.images = false;
  auto r = measure::run_measure(o);
  for (const auto& b : kBackends) {
    std::vector<std::pair<int, double>> by_samples;
    for (const auto& row : r.rows)
      if (row.backend == b)
        for (const auto& [axis, value] : row.axes)
          if (axis == "samples") {  // the AO pass: the G-buffer and blur are the same program for all of them
            auto ao = std::find_if(row.passes.begin(), row.passes.end(), [](const auto& p) { return p.first == "ao"; });
            ASSERT_NE(ao, row.passes.end()) << row.variant;
            by_samples.emplace_back(std::stoi(value), ao->second.min);
          }
    std::sort(by_samples.begin(), by_samples.end());
    ASSERT_EQ(by_samples.size(), 7u) << b;
    // Neighbours (4 vs 6, 24 vs 32) differ by a few percent, within these machines' noise: allow 10 %.
    // Doubling the samples must cost more, with no tolerance.
    for (std::size_t i = 0; i < by_samples.size(); ++i)
      for (std::size_t j = i + 1; j < by_samples.size(); ++j) {
        double tolerance = by_samples[j].first >= 2 * by_samples[i].first ? 1.0 : 0.9;
        EXPECT_GE(by_samples[j].second, tolerance * by_samples[i].second)
            << b << ": " << by_samples[j].first << " samples cost less than " << by_samples[i].first;
      }
    EXPECT_GT(by_samples.back().second, 1.5 * by_samples.front().second) << b << ": 32 vs 4 samples";
  }
}

}  // namespace
}  // namespace aovar::test
