// The cost model (src/decide/cost_model.cpp): a ridge fit, its cross-validated skill, feature specs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "cost_rows.h"
#include "decide/cost_model.h"

namespace aovar::decide {
namespace {
using table::CostRow;
using test::plain_row;  // each row's time is replaced by the formula's

// Rows over the axes the feature extractor reads, with time from a known linear formula.
std::vector<CostRow> synthetic_rows(bool noise_only, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.05);
  std::vector<CostRow> rows;
  const char* algorithms[] = {"alchemy", "hbao", "gtao"};
  const char* blurs[] = {"none", "separable", "bilateral"};
  const char* resolutions[] = {"1", "0.5", "0.25"};
  int i = 0;
  for (int samples : {4, 8, 12, 16, 24})
    for (const char* alg : algorithms)
      for (const char* blur : blurs)
        for (const char* res : resolutions)
          for (bool progressive : {false, true}) {
            double r2 = std::stod(res) * std::stod(res);
            double t = 0.3 + 0.08 * samples * r2 + 0.02 * samples + (std::string(blur) == "bilateral" ? 0.4 : 0) +
                       (std::string(blur) == "separable" ? 0.25 : 0) + (progressive ? 0.1 : 0) +
                       (std::string(alg) == "gtao" ? 0.5 : 0);
            double y = noise_only ? 2 + std::abs(noise(rng)) * 10 : t + noise(rng);
            CostRow r = plain_row("v" + std::to_string(i++), y, 0.1);
            r.axes = {{"algorithm", alg}, {"samples", std::to_string(samples)}, {"blur", blur}, {"resolution", res},
                      {"progressive", progressive ? "true" : "false"}, {"normals", "rgb8"}, {"position", "depth"}};
            rows.push_back(r);
          }
  return rows;
}

TEST(CostModel, FitsALinearFormula) {
  auto rows = synthetic_rows(false, 1);
  auto features = axis_features(rows);
  auto m = fit_cost_model(rows, features);
  EXPECT_EQ(m.n, static_cast<int>(rows.size()));
  EXPECT_GT(m.cv.r2, 0.95);
  EXPECT_GT(m.cv.spearman, 0.95);
  // Unmeasured variant: gtao, 32 samples, bilateral, full resolution, progressive.
  CostRow u = plain_row("unmeasured", 0, std::nullopt);
  u.axes = {{"algorithm", "gtao"}, {"samples", "32"}, {"blur", "bilateral"}, {"resolution", "1"},
            {"progressive", "true"}, {"normals", "rgb8"}, {"position", "depth"}};
  double truth = 0.3 + 0.08 * 32 + 0.02 * 32 + 0.4 + 0.1 + 0.5;
  auto predicted = predict_rows(m, {u});
  ASSERT_EQ(predicted.size(), 1u);
  EXPECT_TRUE(predicted[0].predicted);
  EXPECT_EQ(predicted[0].time_ms.n, 0);
  EXPECT_NEAR(predicted[0].time_ms.min, truth, 0.1 * truth);
}

TEST(CostModel, PureNoiseHasNoSkill) {
  auto rows = synthetic_rows(true, 2);
  auto m = fit_cost_model(rows, axis_features(rows));
  EXPECT_LT(m.cv.r2, 0.1);
  EXPECT_LT(std::abs(m.cv.spearman), 0.3);
}

TEST(CostModel, FeatureSpecsCompose) {
  auto rows = synthetic_rows(false, 3);
  FeatureSpec extra{{"static.alu"}, [](const CostRow& r) { return std::vector<double>{r.static_cost ? r.static_cost->ao.alu : 0.0}; }};
  auto both = axis_features(rows).then(extra);
  EXPECT_EQ(both.names.back(), "static.alu");
  EXPECT_EQ(both.extract(rows[0]).size(), both.names.size());
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {10, 20, 30, 40}), 1.0, 1e-12);
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0, 1e-12);
  EXPECT_THROW(fit_cost_model({rows[0], rows[1]}, both), std::runtime_error);
}

}  // namespace
}  // namespace aovar::decide
