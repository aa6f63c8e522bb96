#include "calibrate/calibrate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "metrics/metrics.h"
#include "render/backend.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"
#include "util/fs.h"
#include "util/glob.h"

namespace aovar::calibrate {
namespace fs = std::filesystem;
using json = nlohmann::json;

std::vector<double> minimize(const std::function<double(const std::vector<double>&)>& f, std::vector<double> start,
                             int max_evaluations, double initial_step, double tolerance, int* evaluations) {
  const std::size_t d = start.size();
  int calls = 0;
  auto clamp01 = [](std::vector<double> x) {
    for (double& v : x) v = std::clamp(v, 0.0, 1.0);
    return x;
  };
  auto eval = [&](const std::vector<double>& x) {
    ++calls;
    return f(x);
  };
  if (d == 0 || max_evaluations < 1) {
    if (evaluations) *evaluations = 0;
    return start;
  }
  // Initial simplex: the start and one step along each axis (inward when the step would leave [0, 1]).
  std::vector<std::vector<double>> x(d + 1, clamp01(start));
  for (std::size_t i = 0; i < d; ++i) x[i + 1][i] += x[i + 1][i] + initial_step <= 1.0 ? initial_step : -initial_step;
  std::vector<double> fx(d + 1);
  for (std::size_t i = 0; i <= d; ++i) fx[i] = eval(x[i]);

  while (calls < max_evaluations) {
    std::vector<std::size_t> order(d + 1);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return fx[a] < fx[b]; });
    std::vector<std::vector<double>> xs;
    std::vector<double> fs_sorted;
    for (std::size_t i : order) xs.push_back(x[i]), fs_sorted.push_back(fx[i]);
    x = xs;
    fx = fs_sorted;
    double size = 0;
    for (std::size_t i = 1; i <= d; ++i)
      for (std::size_t k = 0; k < d; ++k) size = std::max(size, std::abs(x[i][k] - x[0][k]));
    if (size < tolerance) break;

    std::vector<double> centroid(d, 0.0);
    for (std::size_t i = 0; i < d; ++i)
      for (std::size_t k = 0; k < d; ++k) centroid[k] += x[i][k] / static_cast<double>(d);
    auto along = [&](double t) {  // centroid + t (centroid - worst)
      std::vector<double> p(d);
      for (std::size_t k = 0; k < d; ++k) p[k] = centroid[k] + t * (centroid[k] - x[d][k]);
      return clamp01(p);
    };
    auto reflected = along(1.0);
    double fr = eval(reflected);
    if (fr < fx[0]) {
      auto expanded = along(2.0);
      double fe = calls < max_evaluations ? eval(expanded) : std::numeric_limits<double>::infinity();
      if (fe < fr) x[d] = expanded, fx[d] = fe;
      else x[d] = reflected, fx[d] = fr;
    } else if (fr < fx[d - 1]) {
      x[d] = reflected, fx[d] = fr;
    } else {
      auto contracted = along(fr < fx[d] ? 0.5 : -0.5);
      double fc = eval(contracted);
      if (fc < std::min(fr, fx[d])) {
        x[d] = contracted, fx[d] = fc;
      } else {  // shrink toward the best point
        for (std::size_t i = 1; i <= d && calls < max_evaluations; ++i) {
          for (std::size_t k = 0; k < d; ++k) x[i][k] = x[0][k] + 0.5 * (x[i][k] - x[0][k]);
          fx[i] = eval(x[i]);
        }
      }
    }
  }
  std::size_t best = std::min_element(fx.begin(), fx.end()) - fx.begin();
  if (evaluations) *evaluations = calls;
  return x[best];
}

namespace {

std::vector<ViewCase> builtin_cases(const std::string& which) {
  std::vector<ViewCase> out;
  for (const char* s : {"builtin:atrium", "builtin:spheres", "builtin:stairs", "builtin:cornell"}) {
    if (which == "training") {
      out.push_back({s, "overview"});
      out.push_back({s, "closeup"});
    } else {
      out.push_back({s, "background"});
    }
  }
  return out;
}

// The variant a method is fitted with: 16 samples, full resolution, separable blur, r32f depth, highp, the
// buffered RGB8 normal when the method reads normals. Its values then apply to every variant of the method.
std::vector<std::string> fit_globs(const std::string& algorithm) {
  return {algorithm + "-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp", algorithm + "-s16-p0-*-zdep-*-d32-bsep-x1-hp"};
}

struct Case {
  const scene::Scene* scene = nullptr;
  const scene::View* view = nullptr;
  bool training = false;
  reference::ReferenceImage truth;
};

// A parameter marked `fit = true`: its "ao.<name>" key, range and manifest default.
struct FitParam {
  std::string key;
  double min, max, value;
};

std::vector<std::string> algorithms_to_fit(const CalibrateOptions& o, const variants::Manifest& manifest) {
  std::vector<std::string> algorithms = o.algorithms;
  if (algorithms.empty())
    for (const auto& v : manifest.axis_values(variants::Axis::algorithm)) algorithms.push_back(v.text);
  for (const auto& a : algorithms)
    if (!manifest.algorithm(a))
      throw std::runtime_error(
          fmt::format("{}: no algorithm '{}' (aovar list shows them)", manifest.error_prefix(), a));
  return algorithms;
}

compile::CompiledSpace compile_fit_variants(const CalibrateOptions& o, const std::vector<std::string>& algorithms,
                                            variants::Target target) {
  compile::CompileOptions co;
  co.targets = {target};
  for (const auto& a : algorithms)
    for (auto& g : fit_globs(a)) co.globs.push_back(std::move(g));
  co.cache_dir = o.compile_cache;
  auto c = compile::compile_space(o.manifest, co);
  if (!c.ok()) throw std::runtime_error(c.diagnostics.empty() ? "compile failed" : c.diagnostics.front());
  return c;
}

// The training and validation views with their ray-traced references; `scenes` holds each scene once.
std::vector<Case> load_cases(const CalibrateOptions& o, std::map<std::string, scene::Scene>& scenes,
                             const Progress& say) {
  std::vector<Case> cases;
  auto add_cases = [&](const std::vector<ViewCase>& list, bool training) {
    for (const auto& vc : list) {
      auto it = scenes.find(vc.scene);
      if (it == scenes.end()) it = scenes.emplace(vc.scene, scene::load_scene(vc.scene)).first;
      cases.push_back({&it->second, &it->second.view(vc.view), training, {}});
    }
  };
  add_cases(o.training.empty() ? builtin_cases("training") : o.training, true);
  add_cases(o.validation.empty() ? builtin_cases("validation") : o.validation, false);
  for (Case& k : cases) {
    reference::ReferenceOptions ro;
    ro.size = o.size;
    ro.radius = k.scene->ao_radius;
    ro.rays = o.rays;
    ro.mode = o.mode;
    ro.cache_dir = o.reference_cache;
    say(fmt::format("reference {} {}", k.scene->name, k.view->name));
    k.truth = reference::trace_reference(*k.scene, *k.view, ro);
  }
  return cases;
}

// Index of the variant `algorithm` is fitted with (the first fit_globs match).
int fit_variant(const compile::CompiledSpace& c, const variants::Manifest& manifest, const std::string& algorithm) {
  for (const auto& glob : fit_globs(algorithm))
    for (std::size_t v = 0; v < c.space.variants.size(); ++v)
      if (util::glob_match(glob, c.space.variants[v].key)) return static_cast<int>(v);
  throw std::runtime_error(fmt::format("{}: no 16-sample, full-resolution, separable-blur variant of '{}' to fit "
                                       "(the manifest's rules remove it)", manifest.error_prefix(), algorithm));
}

// The fit variant rendered on the cases with given parameter values: one prepared pipeline whose AO draw is
// re-parameterised with set_params, since re-preparing would JIT every time.
class Objective {
 public:
  Objective(runner::VariantRunner& runner, int variant, const std::vector<Case>& cases)
      : runner_(runner), variant_(variant), cases_(cases), plan_(runner.plan(variant, {}, true)) {
    auto ao = std::find_if(plan_.draws.begin(), plan_.draws.end(), [](const auto& d) { return d.name == "ao"; });
    if (ao == plan_.draws.end()) throw std::runtime_error(plan_.variant + ": no ao draw");
    ao_index_ = static_cast<std::size_t>(ao - plan_.draws.begin());
    prepared_ = runner.prepare(plan_);
  }

  // Per-case MSE over the cases of one kind (NaN, Inf and values outside [0, 1] count as an error of 1
  // each, so a parameter set cannot win by breaking pixels).
  std::vector<double> errors(const render::ParamOverrides& values, bool training) {
    runner_.backend().set_params(*prepared_, ao_index_, runner_.plan(variant_, values, true).draws[ao_index_].params);
    std::vector<double> mse;
    for (const Case& k : cases_) {
      if (k.training != training) continue;
      runner_.use_scene(*k.scene);
      const runner::Still still = runner_.render_still(*prepared_, plan_, *k.view, k.scene->ao_radius);
      const metrics::ErrorStats e = runner::score(still.image, k.truth);
      double bad = static_cast<double>(e.health.nan + e.health.inf + e.health.out_of_range);
      double n = std::max<double>(1.0, static_cast<double>(e.health.pixels));
      double sq = e.finite > 0 ? e.rmse * e.rmse : 1.0;
      mse.push_back((sq * static_cast<double>(e.finite) + bad) / n);
    }
    return mse;
  }

 private:
  runner::VariantRunner& runner_;
  int variant_;
  const std::vector<Case>& cases_;
  render::PipelinePlan plan_;
  std::size_t ao_index_ = 0;
  std::unique_ptr<render::PreparedPipeline> prepared_;
};

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double mean_rmse(const std::vector<double>& mse) {
  double s = 0;
  for (double m : mse) s += std::sqrt(m);
  return mse.empty() ? 0.0 : s / static_cast<double>(mse.size());
}

// Per-case MSE before and after the fit, for one kind of case (training or validation).
struct Errors {
  std::vector<double> before, after;
};

// The fit's per-view errors and their means, from the per-case MSE in case order.
void report_errors(AlgorithmFit& fit, const std::vector<Case>& cases, const Errors& train, const Errors& valid) {
  std::size_t ti = 0, vi = 0;
  for (const Case& k : cases) {
    ViewError ve{k.scene->name, k.view->name, k.training, 0, 0};
    if (k.training) ve.rmse_before = std::sqrt(train.before[ti]), ve.rmse_after = std::sqrt(train.after[ti]), ++ti;
    else ve.rmse_before = std::sqrt(valid.before[vi]), ve.rmse_after = std::sqrt(valid.after[vi]), ++vi;
    fit.views.push_back(ve);
  }
  fit.train_rmse_before = mean_rmse(train.before);
  fit.train_rmse_after = mean_rmse(train.after);
  fit.validation_rmse_before = mean_rmse(valid.before);
  fit.validation_rmse_after = mean_rmse(valid.after);
}

// Fits one algorithm's `fit = true` parameters on the training cases, starting from the manifest defaults.
AlgorithmFit fit_algorithm(runner::VariantRunner& runner, const variants::Manifest& manifest,
                           const std::string& algorithm, const std::vector<Case>& cases, const CalibrateOptions& o,
                           const Progress& say) {
  const int variant = fit_variant(runner.compiled(), manifest, algorithm);
  AlgorithmFit fit;
  fit.algorithm = algorithm;
  fit.variant = runner.compiled().space.variants[variant].key;
  std::vector<FitParam> params;
  for (const auto& p : manifest.algorithm(algorithm)->params)
    if (p.fit) params.push_back({"ao." + p.name, p.min, p.max, p.value});
  Objective objective(runner, variant, cases);
  // The search runs over [0, 1] per parameter, mapped onto its range.
  auto values_at = [&](const std::vector<double>& u) {
    render::ParamOverrides values;
    for (std::size_t i = 0; i < params.size(); ++i)
      values[params[i].key] = params[i].min + std::clamp(u[i], 0.0, 1.0) * (params[i].max - params[i].min);
    return values;
  };
  std::vector<double> start;
  for (const auto& p : params) {
    fit.defaults[p.key] = p.value;
    start.push_back(p.max > p.min ? (p.value - p.min) / (p.max - p.min) : 0.0);
  }

  Errors train, valid;
  train.before = objective.errors(fit.defaults, true);
  valid.before = objective.errors(fit.defaults, false);
  int evaluation = 0;
  auto best = minimize(
      [&](const std::vector<double>& u) {
        double m = mean(objective.errors(values_at(u), true));
        say(fmt::format("{}: evaluation {}/{}: training RMSE {:.4f}", algorithm, ++evaluation, o.max_evaluations,
                        std::sqrt(m)));
        return m;
      },
      start, o.max_evaluations, 0.15, 1e-3, &fit.evaluations);
  fit.fitted = values_at(best);
  train.after = objective.errors(fit.fitted, true);
  valid.after = objective.errors(fit.fitted, false);
  // Never worse than the defaults on the training views (the search starts there, but keep it explicit).
  if (mean(train.after) > mean(train.before)) {
    fit.fitted = fit.defaults;
    train.after = train.before;
    valid.after = valid.before;
  }
  report_errors(fit, cases, train, valid);
  return fit;
}

}  // namespace

Calibration calibrate(const CalibrateOptions& o, const Progress& progress) {
  const Progress say = [&](const std::string& s) { if (progress) progress(s); };
  const variants::Target target = render::target_of(o.backend);
  const auto manifest = variants::load_manifest(o.manifest);
  const std::vector<std::string> algorithms = algorithms_to_fit(o, manifest);
  say("compiling the variants to fit");
  const compile::CompiledSpace c = compile_fit_variants(o, algorithms, target);
  std::map<std::string, scene::Scene> scenes;
  const std::vector<Case> cases = load_cases(o, scenes, say);

  runner::RunnerOptions ro;
  ro.backend = o.backend;
  ro.device.threads = o.threads;
  ro.size = o.size;
  runner::VariantRunner runner(c, ro);
  Calibration out;
  out.backend = o.backend;
  out.size = o.size;
  out.rays = o.rays;
  out.mode = o.mode;
  for (const auto& algorithm : algorithms)
    out.fits.push_back(fit_algorithm(runner, manifest, algorithm, cases, o, say));
  return out;
}

void write_calibration(const fs::path& path, const Calibration& cal) {
  json algorithms = json::object();
  for (const auto& f : cal.fits) {
    json views = json::array();
    for (const auto& v : f.views)
      views.push_back({{"scene", v.scene}, {"view", v.view}, {"training", v.training},
                       {"rmse_before", v.rmse_before}, {"rmse_after", v.rmse_after}});
    algorithms[f.algorithm] = {{"variant", f.variant},
                               {"params", f.fitted},
                               {"defaults", f.defaults},
                               {"evaluations", f.evaluations},
                               {"train_rmse_before", f.train_rmse_before},
                               {"train_rmse_after", f.train_rmse_after},
                               {"validation_rmse_before", f.validation_rmse_before},
                               {"validation_rmse_after", f.validation_rmse_after},
                               {"views", views}};
  }
  json doc = {{"tool", "aovar calibrate"},
              {"backend", cal.backend},
              {"size", fmt::format("{}x{}", cal.size.width, cal.size.height)},
              {"rays", cal.rays},
              {"mode", reference::mode_name(cal.mode)},
              {"algorithms", algorithms}};
  util::write_atomic(path, doc.dump(2) + "\n");
}

std::map<std::string, render::ParamOverrides> load_calibration(const fs::path& path) {
  auto text = util::read_file(path);
  if (!text) throw std::runtime_error(fmt::format("{}: error: cannot read the calibration file", util::display_path(path)));
  std::map<std::string, render::ParamOverrides> out;
  try {
    json doc = json::parse(*text);
    for (auto& [algorithm, entry] : doc.at("algorithms").items())
      for (auto& [key, value] : entry.at("params").items()) out[algorithm][key] = value.get<double>();
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: error: not a calibration file ({}); write one with aovar calibrate",
                                         util::display_path(path), e.what()));
  }
  return out;
}

}  // namespace aovar::calibrate
