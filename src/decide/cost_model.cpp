#include "decide/cost_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

namespace aovar::decide {

FeatureSpec FeatureSpec::then(FeatureSpec more) const {
  FeatureSpec out;
  out.names = names;
  out.names.insert(out.names.end(), more.names.begin(), more.names.end());
  out.extract = [a = extract, b = std::move(more.extract)](const table::CostRow& r) {
    auto x = a(r);
    auto y = b(r);
    x.insert(x.end(), y.begin(), y.end());
    return x;
  };
  return out;
}

namespace {
double axis_number(const table::CostRow& r, const char* name, double fallback) {
  auto it = r.axes.find(name);
  if (it == r.axes.end()) return fallback;
  try {
    return std::stod(it->second);
  } catch (const std::exception&) {
    return fallback;
  }
}
std::string axis_text(const table::CostRow& r, const char* name) {
  auto it = r.axes.find(name);
  return it == r.axes.end() ? std::string() : it->second;
}
}  // namespace

FeatureSpec axis_features(const std::vector<table::CostRow>& rows) {
  std::set<std::string> blurs, algorithms;
  for (const auto& r : rows) {
    blurs.insert(axis_text(r, "blur"));
    algorithms.insert(axis_text(r, "algorithm"));
  }
  FeatureSpec f;
  f.names = {"samples", "resolution^2", "samples*resolution^2", "progressive", "normals_from_depth", "position_buffer"};
  for (const auto& b : blurs) f.names.push_back("blur=" + b);
  for (const auto& a : algorithms) f.names.push_back("algorithm=" + a);
  std::vector<std::string> bl(blurs.begin(), blurs.end()), al(algorithms.begin(), algorithms.end());
  f.extract = [bl, al](const table::CostRow& r) {
    double s = axis_number(r, "samples", 0), res = axis_number(r, "resolution", 1);
    std::vector<double> x = {s, res * res, s * res * res, axis_text(r, "progressive") == "true" ? 1.0 : 0.0,
                             axis_text(r, "normals") == "depth" ? 1.0 : 0.0,
                             axis_text(r, "position") == "position" ? 1.0 : 0.0};
    std::string blur = axis_text(r, "blur"), algorithm = axis_text(r, "algorithm");
    for (const auto& b : bl) x.push_back(blur == b ? 1.0 : 0.0);
    for (const auto& a : al) x.push_back(algorithm == a ? 1.0 : 0.0);
    return x;
  };
  return f;
}

double LinearModel::predict(const std::vector<double>& x) const {
  double y = intercept;
  for (std::size_t j = 0; j < weights.size() && j < x.size(); ++j) y += weights[j] * (x[j] - mean[j]) / scale[j];
  return y;
}

LinearModel fit_ridge(const std::vector<std::vector<double>>& x, const std::vector<double>& y, double lambda) {
  std::size_t n = x.size(), p = n ? x[0].size() : 0;
  if (n == 0 || y.size() != n) throw std::runtime_error("fit_ridge: no samples, or x and y differ in length");
  LinearModel m;
  m.mean.assign(p, 0);
  m.scale.assign(p, 1);
  for (const auto& row : x)
    for (std::size_t j = 0; j < p; ++j) m.mean[j] += row[j] / n;
  for (std::size_t j = 0; j < p; ++j) {
    double v = 0;
    for (const auto& row : x) v += (row[j] - m.mean[j]) * (row[j] - m.mean[j]) / n;
    m.scale[j] = v > 1e-24 ? std::sqrt(v) : 1.0;
  }
  double ymean = std::accumulate(y.begin(), y.end(), 0.0) / n;
  // Normal equations (ZᵀZ + λI) w = Zᵀ(y - ȳ), Z standardised; solved by Gaussian elimination with partial pivoting.
  std::vector<std::vector<double>> a(p, std::vector<double>(p + 1, 0));
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> z(p);
    for (std::size_t j = 0; j < p; ++j) z[j] = (x[i][j] - m.mean[j]) / m.scale[j];
    for (std::size_t j = 0; j < p; ++j) {
      for (std::size_t l = 0; l < p; ++l) a[j][l] += z[j] * z[l];
      a[j][p] += z[j] * (y[i] - ymean);
    }
  }
  for (std::size_t j = 0; j < p; ++j) a[j][j] += lambda;
  for (std::size_t c = 0; c < p; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < p; ++r)
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    std::swap(a[c], a[piv]);
    if (std::abs(a[c][c]) < 1e-300) continue;  // only with lambda = 0 and a constant column: weight stays 0
    for (std::size_t r = 0; r < p; ++r) {
      if (r == c) continue;
      double f = a[r][c] / a[c][c];
      if (f == 0) continue;
      for (std::size_t l = c; l <= p; ++l) a[r][l] -= f * a[c][l];
    }
  }
  m.weights.assign(p, 0);
  for (std::size_t j = 0; j < p; ++j) m.weights[j] = std::abs(a[j][j]) < 1e-300 ? 0 : a[j][p] / a[j][j];
  m.intercept = ymean;
  return m;
}

double r_squared(const std::vector<double>& y, const std::vector<double>& f) {
  double mean = std::accumulate(y.begin(), y.end(), 0.0) / y.size(), res = 0, tot = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    res += (y[i] - f[i]) * (y[i] - f[i]);
    tot += (y[i] - mean) * (y[i] - mean);
  }
  return tot > 0 ? 1 - res / tot : 0;
}

namespace {
std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) r[idx[k]] = (i + j) / 2.0 + 1;
    i = j + 1;
  }
  return r;
}
}  // namespace

double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  auto ra = ranks(a), rb = ranks(b);
  double n = a.size(), ma = std::accumulate(ra.begin(), ra.end(), 0.0) / n, mb = std::accumulate(rb.begin(), rb.end(), 0.0) / n;
  double cov = 0, va = 0, vb = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    cov += (ra[i] - ma) * (rb[i] - mb);
    va += (ra[i] - ma) * (ra[i] - ma);
    vb += (rb[i] - mb) * (rb[i] - mb);
  }
  return va > 0 && vb > 0 ? cov / std::sqrt(va * vb) : 0;
}

CrossValidation cross_validate(const std::vector<std::vector<double>>& x, const std::vector<double>& y,
                               double lambda, int k) {
  if (k < 2 || x.size() < static_cast<std::size_t>(k))
    throw std::runtime_error("cross_validate: need at least k >= 2 samples (" + std::to_string(x.size()) + " for k = " +
                             std::to_string(k) + ")");
  CrossValidation cv;
  cv.k = k;
  cv.held_out.assign(y.size(), 0);
  for (int fold = 0; fold < k; ++fold) {
    std::vector<std::vector<double>> tx;
    std::vector<double> ty;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (static_cast<int>(i % k) != fold) {
        tx.push_back(x[i]);
        ty.push_back(y[i]);
      }
    LinearModel m = fit_ridge(tx, ty, lambda);
    for (std::size_t i = fold; i < x.size(); i += k) cv.held_out[i] = m.predict(x[i]);
  }
  cv.r2 = r_squared(y, cv.held_out);
  cv.spearman = spearman(y, cv.held_out);
  return cv;
}

CostModel fit_cost_model(const std::vector<table::CostRow>& rows, const FeatureSpec& features, double lambda, int k,
                         const Target& target) {
  std::vector<std::vector<double>> x;
  std::vector<double> y;
  for (const auto& r : rows)
    if (!r.predicted) {
      x.push_back(features.extract(r));
      y.push_back(target ? target(r) : r.time_ms.decision());
    }
  if (x.size() < static_cast<std::size_t>(k))
    throw std::runtime_error("cost model: " + std::to_string(x.size()) + " measured rows; need at least " +
                             std::to_string(k) + " for " + std::to_string(k) + "-fold cross-validation");
  CostModel m;
  m.features = features;
  m.n = static_cast<int>(x.size());
  m.cv = cross_validate(x, y, lambda, k);
  m.model = fit_ridge(x, y, lambda);
  return m;
}

std::vector<table::CostRow> predict_rows(const CostModel& model, std::vector<table::CostRow> rows) {
  for (auto& r : rows) {
    double t = model.predict(r);
    r.time_ms = {t, t, t, 0, t};
    r.gbuffer_ms.reset();  // the model predicts the frame, not its split
    r.predicted = true;
    r.pareto = false;
  }
  return rows;
}

}  // namespace aovar::decide
