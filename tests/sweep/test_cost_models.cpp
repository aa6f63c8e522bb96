// The sweep's cost models (src/sweep/cost_models.h): a model is predictive only with cross-validated R² >= 0
// and held-out Spearman >= the threshold; a group with none refuses to predict, and its models are shown
// as "not predictive (reason)", not as results.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <fmt/format.h>

#include "sweep/cost_models.h"
#include "sweep/text.h"

namespace {
using namespace aovar;
using sweep::Group;

// A measured row whose static features (work per pixel, AO reads, weighted classes) all grow with `work`;
// the blur and progressive axes vary too, as in a real sweep.
table::CostRow model_row(const std::string& view, int i, double work, double time) {
  table::CostRow r;
  r.variant = "v" + std::to_string(i);
  r.scene = "builtin:atrium";
  r.view = view;
  r.backend = "lavapipe";
  r.size = "64x36";
  r.time_ms = {time, time, time, 10};
  static const char* blurs[] = {"none", "separable", "bilateral"};
  r.axes = {{"algorithm", "alchemy"}, {"resolution", "1"}, {"blur", blurs[i % 3]}, {"progressive", i % 2 ? "true" : "false"}};
  table::StaticCost s;
  s.work_per_pixel = work;
  s.ao.fetches.depth = work / 10;
  s.ao.alu = work / 2;
  s.weighted_ao.alu = work / 2;
  s.weighted_ao.fetches = work / 10;
  s.weighted_others.alu = 3 + i % 3;
  r.static_cost = s;
  return r;
}

double work_of(int i) { return 20 + 7.0 * i; }

// 40 rows of growing static work, each timed by time_of(its work, a generator seeded with `seed`).
template <class TimeOf>
std::vector<table::CostRow> rows_timed(const std::string& view, unsigned seed, TimeOf time_of) {
  std::mt19937 rng(seed);
  std::vector<table::CostRow> rows;
  for (int i = 0; i < 40; ++i) rows.push_back(model_row(view, i, work_of(i), time_of(work_of(i), rng)));
  return rows;
}

// Time that has nothing to do with the features: uniform in [1, 3] ms from a fixed seed.
std::vector<table::CostRow> unrelated_rows(const std::string& view) {
  return rows_timed(view, 18, [](double, std::mt19937& rng) { return std::uniform_real_distribution<double>(1.0, 3.0)(rng); });
}

// Time that is a clean linear function of the work per pixel (plus 1 % noise).
double linear_time(double work) { return 0.2 + 0.01 * work; }
std::vector<table::CostRow> linear_rows(const std::string& view) {
  return rows_timed(view, 5, [](double work, std::mt19937& rng) {
    return linear_time(work) * (1 + std::normal_distribution<double>(0, 0.01)(rng));
  });
}

std::vector<table::CostRow> both(std::vector<table::CostRow> a, const std::vector<table::CostRow>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

const Group kUnrelated{"builtin:atrium", "unrelated", "lavapipe"}, kLinear{"builtin:atrium", "linear", "lavapipe"};

std::vector<sweep::ModelFit> fits_of(const sweep::GroupModels& gm, const std::string& view) {
  std::vector<sweep::ModelFit> out;
  for (const auto& m : gm.models)
    if (m.view == view) out.push_back(m);
  return out;
}

TEST(CostModels, JudgeNeedsNonNegativeR2AndTheSpearmanThreshold) {
  EXPECT_DOUBLE_EQ(sweep::kMinModelSpearman, 0.7);
  EXPECT_TRUE(sweep::judge_model(0.0, 0.7).predictive) << "both bounds are inclusive";
  auto low_rho = sweep::judge_model(0.4, 0.59);
  EXPECT_FALSE(low_rho.predictive);
  EXPECT_EQ(low_rho.reason, "held-out Spearman 0.590 < 0.70");
  auto low_r2 = sweep::judge_model(-51.7, 0.9);
  EXPECT_FALSE(low_r2.predictive);
  EXPECT_EQ(low_r2.reason, "cross-validated R² -51.7 < 0");
  auto both_low = sweep::judge_model(-0.5, 0.1);
  EXPECT_NE(both_low.reason.find("R² -0.5 < 0"), std::string::npos) << both_low.reason;
  EXPECT_NE(both_low.reason.find("Spearman 0.100 < 0.70"), std::string::npos) << both_low.reason;
  EXPECT_FALSE(sweep::judge_model(std::nan(""), 0.9).predictive) << "a NaN skill is no skill";
  EXPECT_FALSE(sweep::judge_model(0.5, std::nan("")).predictive);
  EXPECT_TRUE(sweep::judge_model(0.5, 0.5, 0.4).predictive) << "the threshold is a parameter";
  EXPECT_FALSE(sweep::judge_model(0.5, 0.5, 0.6).predictive);
}

TEST(CostModels, TimeUnrelatedToTheFeaturesIsNotPredictiveAndRefusesToPredict) {
  auto gm = sweep::fit_group_models(both(unrelated_rows("unrelated"), linear_rows("linear")));
  auto fits = fits_of(gm, "unrelated");
  ASSERT_GE(fits.size(), 2u) << "compact and weighted-class models at least";
  const sweep::ModelFit* best = nullptr;
  for (const auto& m : fits) {
    // The verdict follows the numbers (not the other way round), and the reason names what fails.
    EXPECT_EQ(m.predictive, m.cv_r2 >= 0 && m.cv_spearman >= sweep::kMinModelSpearman) << m.features;
    EXPECT_FALSE(m.predictive) << m.features << ": R² " << m.cv_r2 << ", Spearman " << m.cv_spearman;
    EXPECT_FALSE(m.predicts) << m.features;
    EXPECT_EQ(m.verdict, "not predictive: " + m.reason);
    if (m.cv_spearman < sweep::kMinModelSpearman) {
      EXPECT_NE(m.reason.find(fmt::format("held-out Spearman {:.3f} < 0.70", m.cv_spearman)), std::string::npos) << m.reason;
    }
    if (m.cv_r2 < 0) { EXPECT_NE(m.reason.find("cross-validated R² "), std::string::npos) << m.reason; }
    EXPECT_EQ(sweep::not_predictive_label(m), "not predictive (" + m.reason + ")");
    if (!best || m.cv_spearman > best->cv_spearman) best = &m;
  }
  EXPECT_FALSE(gm.best.count(kUnrelated)) << "no predicting model among not predictive ones";
  ASSERT_TRUE(gm.unpredictable.count(kUnrelated));
  EXPECT_EQ(gm.unpredictable.at(kUnrelated), best->reason) << "the reason of the best held-out Spearman";

  // The predict path refuses this group, in one line naming it, why, and what to do.
  try {
    sweep::predicting_model(gm, kUnrelated);
    ADD_FAILURE() << "predicting_model must refuse a group with no predictive model";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what, "sweep --predict: no predictive cost model for builtin:atrium/unrelated/lavapipe (best: " + best->reason +
                        "); measure these variants or lower --min-model-spearman");
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  // The other group of the same fit is judged on its own rows and still predicts.
  EXPECT_NE(sweep::predicting_model(gm, kLinear), nullptr);
  // A group too small for any model has none, and no refusal: it gets no predicted rows, as before.
  auto few = unrelated_rows("small");
  few.resize(5);
  auto small = sweep::fit_group_models(few);
  EXPECT_EQ(sweep::predicting_model(small, {"builtin:atrium", "small", "lavapipe"}), nullptr);
}

TEST(CostModels, NotPredictiveModelsAreLabelledInTheJsonAndTheSweepText) {
  auto gm = sweep::fit_group_models(both(unrelated_rows("unrelated"), linear_rows("linear")));
  auto j = table::to_json(gm.models);
  ASSERT_EQ(j.size(), gm.models.size());
  EXPECT_EQ(table::model_fits_from_json(j), gm.models) << "cost_table.json gives back the fits it was written from";
  for (std::size_t i = 0; i < j.size(); ++i) {
    EXPECT_EQ(j[i].at("predictive").get<bool>(), gm.models[i].predictive);
    EXPECT_EQ(j[i].at("verdict").get<std::string>(), gm.models[i].verdict);
    EXPECT_EQ(j[i].at("verdict").get<std::string>().rfind(gm.models[i].predictive ? "predictive: " : "not predictive: ", 0), 0u);
  }
  sweep::SweepResult r;
  r.cost_models = gm.models;
  sweep::SweepOptions o;
  o.out = "/tmp/sw";
  const std::string s = sweep::notes_text(r, o, {});
  for (const auto& m : gm.models) {
    const std::string head = fmt::format("# cost model {} {} {}: {} rows", m.scene, m.view, m.backend, m.rows);
    if (m.predictive) {
      EXPECT_NE(s.find(head + fmt::format(", cross-validated R2 {:.3f}", m.cv_r2)), std::string::npos) << s;
    } else {
      EXPECT_NE(s.find(head + ", " + m.features + " features: not predictive (" + m.reason + ")"), std::string::npos) << s;
      EXPECT_EQ(s.find(head + fmt::format(", cross-validated R2 {:.3f}", m.cv_r2)), std::string::npos)
          << "a not predictive model's R² is a reason, not a result:\n" << s;
    }
  }
}

TEST(CostModels, TimeLinearInAStaticFeatureIsPredictiveAndPredictsRows) {
  auto gm = sweep::fit_group_models(linear_rows("linear"));
  int predicting = 0;
  for (const auto& m : fits_of(gm, "linear")) {
    EXPECT_EQ(m.predictive, m.cv_r2 >= 0 && m.cv_spearman >= sweep::kMinModelSpearman) << m.features;
    EXPECT_EQ(m.verdict, (m.predictive ? "predictive: " : "not predictive: ") + m.reason);
    EXPECT_TRUE(!m.predicts || m.predictive) << "only a predictive model predicts";
    predicting += m.predicts;
  }
  EXPECT_EQ(predicting, 1);
  EXPECT_FALSE(gm.unpredictable.count(kLinear));
  const decide::CostModel* model = sweep::predicting_model(gm, kLinear);
  ASSERT_NE(model, nullptr);
  EXPECT_GE(model->cv.spearman, sweep::kMinModelSpearman);
  // An unmeasured variant inside the measured range: its predicted time is the formula's, within 5 %.
  table::CostRow unmeasured = model_row("linear", 1000, 150.5, 0);
  unmeasured.time_ms = {};
  auto predicted = decide::predict_rows(*model, {unmeasured});
  ASSERT_EQ(predicted.size(), 1u);
  EXPECT_TRUE(predicted[0].predicted);
  EXPECT_NEAR(predicted[0].time_ms.min, linear_time(150.5), 0.05 * linear_time(150.5));

  // The same rows under an unreachable threshold: nothing may predict, and the refusal says why.
  auto strict = sweep::fit_group_models(linear_rows("linear"), 1.01);
  for (const auto& m : strict.models) EXPECT_FALSE(m.predictive) << m.features;
  ASSERT_TRUE(strict.unpredictable.count(kLinear));
  EXPECT_NE(strict.unpredictable.at(kLinear).find("< 1.01"), std::string::npos) << strict.unpredictable.at(kLinear);
  EXPECT_THROW(sweep::predicting_model(strict, kLinear), std::runtime_error);
}

}  // namespace
