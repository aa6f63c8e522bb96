#include "calibrate/calibrate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "metrics/metrics.h"
#include "render/backend.h"
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

variants::Target target_of(const std::string& backend) {
  if (backend == "lavapipe") return variants::Target::vulkan;
  if (backend == "osmesa") return variants::Target::gl45;
  throw std::runtime_error(fmt::format("unknown backend '{}' (use lavapipe or osmesa)", backend));
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

}  // namespace

Calibration calibrate(const CalibrateOptions& o, const Progress& progress) {
  auto say = [&](const std::string& s) { if (progress) progress(s); };
  const variants::Target target = target_of(o.backend);
  auto manifest = variants::load_manifest(o.manifest);
  std::vector<std::string> algorithms = o.algorithms;
  if (algorithms.empty())
    for (const auto& v : manifest.axis_values(variants::Axis::algorithm)) algorithms.push_back(v.text);
  for (const auto& a : algorithms)
    if (!manifest.algorithm(a))
      throw std::runtime_error(fmt::format("{}: no algorithm '{}' (aovar list shows them)", manifest.error_prefix(), a));

  compile::CompileOptions co;
  co.targets = {target};
  for (const auto& a : algorithms)
    for (auto& g : fit_globs(a)) co.globs.push_back(std::move(g));
  co.cache_dir = o.compile_cache;
  say("compiling the variants to fit");
  auto c = compile::compile_space(o.manifest, co);
  if (!c.ok())
    throw std::runtime_error(c.diagnostics.empty() ? "compile failed" : c.diagnostics.front());

  // Scenes, views and their references.
  std::map<std::string, scene::Scene> scenes;
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

  render::BackendOptions bo;
  bo.threads = o.threads;
  auto backend = render::make_backend(o.backend, bo);
  Calibration out;
  out.backend = o.backend;
  out.size = o.size;
  out.rays = o.rays;
  out.mode = o.mode;

  for (const auto& algorithm : algorithms) {
    int variant = -1;
    for (const auto& glob : fit_globs(algorithm)) {
      for (std::size_t v = 0; v < c.space.variants.size() && variant < 0; ++v)
        if (util::glob_match(glob, c.space.variants[v].key)) variant = static_cast<int>(v);
      if (variant >= 0) break;
    }
    if (variant < 0)
      throw std::runtime_error(fmt::format("{}: no 16-sample, full-resolution, separable-blur variant of '{}' to fit "
                                           "(the manifest's rules remove it)", manifest.error_prefix(), algorithm));
    AlgorithmFit fit;
    fit.algorithm = algorithm;
    fit.variant = c.space.variants[variant].key;
    struct Fitted {
      std::string key;
      double min, max, value;
    };
    std::vector<Fitted> params;
    for (const auto& p : manifest.algorithm(algorithm)->params)
      if (p.fit) params.push_back({"ao." + p.name, p.min, p.max, p.value});

    render::PipelinePlan plan = render::plan_pipeline(c, variant, target);
    auto ao_draw = std::find_if(plan.draws.begin(), plan.draws.end(), [](const auto& d) { return d.name == "ao"; });
    if (ao_draw == plan.draws.end()) throw std::runtime_error(fit.variant + ": no ao draw");
    const std::size_t ao_index = static_cast<std::size_t>(ao_draw - plan.draws.begin());
    auto prepared = backend->prepare(plan, o.size);

    const scene::Scene* current = nullptr;
    // Renders every case of one kind with the given values; returns per-case MSE (NaN, Inf and values
    // outside [0, 1] count as an error of 1 each, so a parameter set cannot win by breaking pixels).
    auto errors = [&](const render::ParamOverrides& values, bool training) {
      backend->set_params(*prepared, ao_index,
                          render::plan_pipeline(c, variant, target, values).draws[ao_index].params);
      std::vector<double> mse;
      for (const Case& k : cases) {
        if (k.training != training) continue;
        if (current != k.scene) backend->set_scene(*k.scene), current = k.scene;
        render::FrameSetup fsu;
        fsu.view = k.view;
        fsu.static_camera = true;
        fsu.radius = k.scene->ao_radius;
        for (int f = 0; f < 2; ++f) {
          fsu.frame = f;
          backend->render(*prepared, fsu);
        }
        auto img = backend->read_result(*prepared);
        auto e = metrics::compare(img, k.truth.visibility, k.truth.background);
        double bad = static_cast<double>(e.health.nan + e.health.inf + e.health.out_of_range);
        double n = std::max<double>(1.0, static_cast<double>(e.health.pixels));
        double sq = e.finite > 0 ? e.rmse * e.rmse : 1.0;
        mse.push_back((sq * static_cast<double>(e.finite) + bad) / n);
      }
      return mse;
    };
    auto mean = [](const std::vector<double>& v) {
      return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    };
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
    auto train_before = errors(fit.defaults, true);
    auto valid_before = errors(fit.defaults, false);
    int evaluation = 0;
    auto best = minimize(
        [&](const std::vector<double>& u) {
          double m = mean(errors(values_at(u), true));
          say(fmt::format("{}: evaluation {}/{}: training RMSE {:.4f}", algorithm, ++evaluation, o.max_evaluations,
                          std::sqrt(m)));
          return m;
        },
        start, o.max_evaluations, 0.15, 1e-3, &fit.evaluations);
    fit.fitted = values_at(best);
    auto train_after = errors(fit.fitted, true);
    auto valid_after = errors(fit.fitted, false);
    // Never worse than the defaults on the training views (the search starts there, but keep it explicit).
    if (mean(train_after) > mean(train_before)) {
      fit.fitted = fit.defaults;
      train_after = train_before;
      valid_after = valid_before;
    }
    std::size_t ti = 0, vi = 0;
    for (const Case& k : cases) {
      ViewError ve{k.scene->name, k.view->name, k.training, 0, 0};
      if (k.training) ve.rmse_before = std::sqrt(train_before[ti]), ve.rmse_after = std::sqrt(train_after[ti]), ++ti;
      else ve.rmse_before = std::sqrt(valid_before[vi]), ve.rmse_after = std::sqrt(valid_after[vi]), ++vi;
      fit.views.push_back(ve);
    }
    auto mean_rmse = [](const std::vector<double>& mse) {
      double s = 0;
      for (double m : mse) s += std::sqrt(m);
      return mse.empty() ? 0.0 : s / static_cast<double>(mse.size());
    };
    fit.train_rmse_before = mean_rmse(train_before);
    fit.train_rmse_after = mean_rmse(train_after);
    fit.validation_rmse_before = mean_rmse(valid_before);
    fit.validation_rmse_after = mean_rmse(valid_after);
    out.fits.push_back(std::move(fit));
  }
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
