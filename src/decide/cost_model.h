#pragma once
// Cost model: predicts the decision time (time_ms.paired, else min) from numeric static features with ridge-regularised least squares,
// k-fold cross-validated (R² and Spearman ρ on held-out folds). Features are a named vector per row;
// FeatureSpec::then appends another extractor (the static analyser's counts, later).
#include <functional>
#include <string>
#include <vector>

#include "table/table.h"

namespace aovar::decide {

struct FeatureSpec {
  std::vector<std::string> names;
  std::function<std::vector<double>(const table::CostRow&)> extract;  // returns names.size() values
  // This spec's features followed by `more`'s.
  FeatureSpec then(FeatureSpec more) const;
};

// From the axes: samples, resolution factor squared, samples x resolution², blur one-hot, progressive,
// normals from depth, position buffer, algorithm one-hot. The one-hot columns are the values found in
// `rows` (sorted), so a spec fitted on some rows applies to others of the same manifest.
FeatureSpec axis_features(const std::vector<table::CostRow>& rows);

struct LinearModel {
  std::vector<double> mean, scale;  // feature standardisation (train set)
  std::vector<double> weights;      // on standardised features
  double intercept = 0;
  double predict(const std::vector<double>& x) const;
};

// Minimises |y - Xw - b|² + lambda |w|² on standardised columns (intercept not penalised).
LinearModel fit_ridge(const std::vector<std::vector<double>>& x, const std::vector<double>& y, double lambda);

double r_squared(const std::vector<double>& measured, const std::vector<double>& predicted);
double spearman(const std::vector<double>& a, const std::vector<double>& b);  // average ranks for ties

struct CrossValidation {
  int k = 5;
  double r2 = 0, spearman = 0;
  std::vector<double> held_out;  // each sample's prediction by the model fitted without its fold
};
// Deterministic folds: sample i is in fold i % k. Needs at least k samples.
CrossValidation cross_validate(const std::vector<std::vector<double>>& x, const std::vector<double>& y,
                               double lambda, int k = 5);

// What a model predicts for a row; default: time_ms.decision() (paired when known, else min).
using Target = std::function<double(const table::CostRow&)>;

struct CostModel {
  FeatureSpec features;
  LinearModel model;   // fitted on all rows
  CrossValidation cv;
  int n = 0;
  double predict(const table::CostRow& row) const { return model.predict(features.extract(row)); }
};

// Fits on the measured rows (predicted == false) of `rows`; the caller picks one scene/view/backend/size.
// Throws std::runtime_error with fewer than k measured rows.
CostModel fit_cost_model(const std::vector<table::CostRow>& rows, const FeatureSpec& features, double lambda = 1e-2,
                         int k = 5, const Target& target = {});

// Copies of `unmeasured` with time_ms (min = median = p90 = paired) from the model, n = 0, predicted = true,
// and no G-buffer split (gbuffer_ms unknown).
std::vector<table::CostRow> predict_rows(const CostModel& model, std::vector<table::CostRow> unmeasured);

}  // namespace aovar::decide
