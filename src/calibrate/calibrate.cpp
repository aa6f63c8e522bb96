#include "calibrate/calibrate.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "compile/generate.h"
#include "metrics/metrics.h"
#include "render/backend.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"
#include "util/glob.h"

namespace aovar::calibrate {

namespace {

// The variant a method is fitted with: 16 samples, full resolution, separable blur, r32f depth, highp, the
// buffered RGB8 normal when the method reads normals (normals "buffer") or normals from depth ("depth").
// Its values then apply to every variant of the method.
std::vector<std::string> fit_globs(const std::string& algorithm, const std::string& normals) {
  const std::string token = normals == "depth" ? "ndep" : "nrgb8";
  return {algorithm + "-s16-p0-" + token + "-zdep-rst-d32-bsep-x1-hp", algorithm + "-s16-p0-" + token + "-zdep-*-d32-bsep-x1-hp",
          algorithm + "-s16-p0-*-zdep-*-d32-bsep-x1-hp"};
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

// What one fit renders: a variant, standing for its algorithm or for itself.
struct Target {
  std::string algorithm;
  int variant = 0;
  bool per_variant = false;
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
  compile::CompileOptions co{o.scope};
  co.scope.targets = {target};
  co.globs = o.variants;
  if (co.globs.empty())
    for (const auto& a : algorithms)
      for (auto& g : fit_globs(a, o.fit_normals)) co.globs.push_back(std::move(g));
  auto c = compile::compile_space(co);
  if (!c.ok()) throw std::runtime_error(c.diagnostics.empty() ? "compile failed" : c.diagnostics.front());
  return c;
}

// Index of the variant `algorithm` is fitted with (the first fit_globs match).
int fit_variant(const compile::CompiledSpace& c, const variants::Manifest& manifest, const std::string& algorithm,
                const std::string& normals) {
  for (const auto& glob : fit_globs(algorithm, normals))
    for (std::size_t v = 0; v < c.space.variants.size(); ++v)
      if (util::glob_match(glob, c.space.variants[v].key)) return static_cast<int>(v);
  throw std::runtime_error(fmt::format("{}: no 16-sample, full-resolution, separable-blur variant of '{}' to fit "
                                       "(the manifest's rules remove it)", manifest.error_prefix(), algorithm));
}

// One fit per algorithm, or (with --variants) one per selected variant, filtered by --algorithms.
std::vector<Target> fit_targets(const CalibrateOptions& o, const compile::CompiledSpace& c,
                                const std::vector<std::string>& algorithms) {
  std::vector<Target> out;
  if (o.variants.empty()) {
    for (const auto& a : algorithms) out.push_back({a, fit_variant(c, c.manifest, a, o.fit_normals), false});
    return out;
  }
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto& point = c.space.variants[v].point;
    std::string a = c.manifest.value(variants::Axis::algorithm, point[variants::index(variants::Axis::algorithm)]).text;
    if (std::find(algorithms.begin(), algorithms.end(), a) != algorithms.end())
      out.push_back({a, static_cast<int>(v), true});
  }
  if (out.empty()) throw std::runtime_error("calibrate: error: --variants selects no variant of the algorithms to fit");
  return out;
}

// The training and held-out views with their ray-traced references; `scenes` holds each scene once.
std::vector<Case> load_cases(const CalibrateOptions& o, const ViewSplit& split, std::map<std::string, scene::Scene>& scenes,
                             const Progress& say) {
  std::vector<Case> cases;
  scene::LoadOptions lo;
  lo.views_file = o.views_file;
  auto add_cases = [&](const std::vector<ViewCase>& list, bool training) {
    for (const auto& vc : list) {
      auto it = scenes.find(vc.scene);
      if (it == scenes.end()) it = scenes.emplace(vc.scene, scene::load_scene(vc.scene, lo)).first;
      cases.push_back({&it->second, &it->second.view(vc.view), training, {}});
    }
  };
  add_cases(split.training, true);
  add_cases(split.holdout, false);
  for (Case& k : cases) {
    reference::ReferenceOptions ro;
    ro.size = o.size;
    ro.radius = k.scene->ao_radius;
    ro.rays = o.rays;
    ro.mode = o.mode;
    ro.cache_dir = o.scope.cache_dir;
    say(fmt::format("reference {} {}", k.scene->name, k.view->name));
    k.truth = reference::trace_reference(*k.scene, *k.view, ro);
  }
  return cases;
}

// The fit variant rendered on the cases with given parameter values: one prepared pipeline whose AO draw is
// re-parameterised with set_params, since re-preparing would JIT every time.
class Objective {
 public:
  Objective(runner::VariantRunner& runner, int variant, const std::vector<Case>& cases)
      : runner_(runner), variant_(variant), cases_(cases), plan_(runner.plan(variant, {}, true)) {
    // The index in the plan the backend runs at this size (MIP draws before the AO draw may be dropped).
    ao_index_ = render::draw_index_at_size(plan_, runner.size(), "ao");
    prepared_ = runner.prepare(plan_);
    for (const Case& k : cases_) truths_.emplace_back(k.truth.visibility, k.truth.background);
  }

  // Per-case MSE over the cases of one kind (NaN, Inf and values outside [0, 1] count as an error of 1
  // each, so a parameter set cannot win by breaking pixels).
  std::vector<double> errors(const render::ParamOverrides& values, bool training) {
    const auto ran = render::plan_for_size(runner_.plan(variant_, values, true), runner_.size());
    runner_.backend().set_params(*prepared_, ao_index_, ran.draws[ao_index_].params);
    std::vector<double> mse;
    for (std::size_t c = 0; c < cases_.size(); ++c) {
      const Case& k = cases_[c];
      if (k.training != training) continue;
      runner_.use_scene(*k.scene);
      const runner::Still still = runner_.render_still(*prepared_, plan_, *k.view, k.scene->ao_radius);
      const metrics::ErrorStats e = metrics::compare(still.image, truths_[c]);  // as runner::score, reference once
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
  std::vector<metrics::PreparedReference> truths_;  // per case, of cases_[i].truth
};

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double mean_rmse(const std::vector<double>& mse) {
  double s = 0;
  for (double m : mse) s += std::sqrt(m);
  return mse.empty() ? 0.0 : s / static_cast<double>(mse.size());
}

// Per-case MSE before and after the fit, for one kind of case (training or held out).
struct Errors {
  std::vector<double> before, after;
};

// The fit's per-view errors and their means, from the per-case MSE in case order.
void report_errors(Fit& fit, const std::vector<Case>& cases, const Errors& train, const Errors& held) {
  std::size_t ti = 0, hi = 0;
  for (const Case& k : cases) {
    ViewError ve{k.scene->name, k.view->name, k.training, 0, 0};
    if (k.training) ve.rmse_before = std::sqrt(train.before[ti]), ve.rmse_after = std::sqrt(train.after[ti]), ++ti;
    else ve.rmse_before = std::sqrt(held.before[hi]), ve.rmse_after = std::sqrt(held.after[hi]), ++hi;
    fit.views.push_back(ve);
  }
  fit.train_rmse_before = mean_rmse(train.before);
  fit.train_rmse_after = mean_rmse(train.after);
  fit.holdout_rmse_before = mean_rmse(held.before);
  fit.holdout_rmse_after = mean_rmse(held.after);
}

// Fits one target's `fit = true` parameters on the training cases, starting from the manifest defaults.
Fit fit_target(runner::VariantRunner& runner, const variants::Manifest& manifest, const Target& target,
               const std::vector<Case>& cases, const CalibrateOptions& o, const Progress& say) {
  Fit fit;
  fit.algorithm = target.algorithm;
  fit.variant = runner.compiled().space.variants[target.variant].key;
  fit.per_variant = target.per_variant;
  fit.budget = o.budget.max_evaluations;
  std::vector<FitParam> params;
  for (const auto& p : manifest.algorithm(target.algorithm)->params)
    if (p.fit) params.push_back({"ao." + p.name, p.min, p.max, p.value});
  Objective objective(runner, target.variant, cases);
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

  Errors train, held;
  train.before = objective.errors(fit.defaults, true);
  held.before = objective.errors(fit.defaults, false);
  int evaluation = 0;
  const std::string name = target.per_variant ? fit.variant : fit.algorithm;
  fit.search = minimize(
      [&](const std::vector<double>& u) {
        double m = mean(objective.errors(values_at(u), true));
        say(fmt::format("{}: evaluation {}/{}: training RMSE {:.4f}", name, ++evaluation, o.budget.max_evaluations,
                        std::sqrt(m)));
        return m;
      },
      start, o.budget);
  fit.fitted = values_at(fit.search.x);
  train.after = objective.errors(fit.fitted, true);
  held.after = objective.errors(fit.fitted, false);
  // Never worse than the defaults on the training views (the search starts there, but keep it explicit).
  if (mean(train.after) > mean(train.before)) {
    fit.fitted = fit.defaults;
    train.after = train.before;
    held.after = held.before;
  }
  report_errors(fit, cases, train, held);
  return fit;
}

// The targets fitted `fits_at_once` at a time (0: one per core), each worker with its own runner: the fit renders
// small images one after another, which leaves cores idle (ship's fit used 1.3 of 2 cores one at a time). A
// runner (its device or GL context) is created on the thread that renders with it, since a GL context is current
// on one thread. The fits are independent and deterministic (BOBYQA/COBYLA), so the result does not depend on
// how many run at once; it is returned in target order, and the first failure in that order is rethrown.
std::vector<Fit> fit_targets_at_once(const compile::CompiledSpace& c, const runner::RunnerOptions& ro,
                                     const variants::Manifest& manifest, const std::vector<Target>& targets,
                                     const std::vector<Case>& cases, const CalibrateOptions& o, const Progress& say) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::min<std::size_t>(targets.size(), o.fits_at_once > 0 ? unsigned(o.fits_at_once) : cores);
  std::vector<std::optional<Fit>> fits(targets.size());
  std::vector<std::exception_ptr> errors(targets.size());
  std::atomic<std::size_t> next{0};
  std::mutex say_mutex;
  const Progress say_locked = [&](const std::string& s) {
    std::lock_guard lock(say_mutex);
    say(s);
  };
  auto work = [&] {
    std::optional<runner::VariantRunner> runner;
    for (std::size_t i; (i = next++) < targets.size();) {
      try {
        if (!runner) runner.emplace(c, ro);
        fits[i] = fit_target(*runner, manifest, targets[i], cases, o, say_locked);
      } catch (...) {
        errors[i] = std::current_exception();
        next = targets.size();  // start no other fit
      }
    }
  };
  if (workers <= 1) {
    work();
  } else {
    std::vector<std::jthread> pool;
    for (std::size_t w = 0; w < workers; ++w) pool.emplace_back(work);
  }
  std::vector<Fit> out;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (errors[i]) std::rethrow_exception(errors[i]);
    if (fits[i]) out.push_back(std::move(*fits[i]));
  }
  return out;
}

}  // namespace

Calibration calibrate(const CalibrateOptions& o, const Progress& progress) {
  const Progress say = [&](const std::string& s) { if (progress) progress(s); };
  if (o.fit_normals != "buffer" && o.fit_normals != "depth")
    throw std::runtime_error("calibrate: error: --normals must be buffer or depth, not '" + o.fit_normals + "'");
  const variants::Target target = render::target_of(o.backend);
  const variants::Manifest& manifest = o.scope.manifest.get();
  const std::vector<std::string> algorithms = algorithms_to_fit(o, manifest);
  say("compiling the variants to fit");
  const compile::CompiledSpace c = compile_fit_variants(o, algorithms, target);
  const std::vector<Target> targets = fit_targets(o, c, algorithms);
  const ViewSplit split = o.views.training.empty() ? builtin_split() : o.views;
  std::map<std::string, scene::Scene> scenes;
  const std::vector<Case> cases = load_cases(o, split, scenes, say);

  runner::RunnerOptions ro;
  ro.backend = o.backend;
  ro.device.threads = o.scope.threads;
  ro.device.gbuffer_cache = o.scope.cache_dir;
  ro.size = o.size;
  Calibration out;
  out.backend = o.backend;
  out.size = o.size;
  out.rays = o.rays;
  out.mode = o.mode;
  out.views = split;
  out.fits = fit_targets_at_once(c, ro, manifest, targets, cases, o, say);
  return out;
}

}  // namespace aovar::calibrate
