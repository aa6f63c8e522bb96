#include "calibrate/optimize.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlopt.h>

namespace aovar::calibrate {
namespace {

// What the NLopt callback sees: the objective, the record of the search and the first exception of f
// (NLopt is C: an exception must not unwind through it, so it is kept and the search is stopped).
struct Search {
  const std::function<double(const std::vector<double>&)>& f;
  Minimum& out;
  nlopt_opt opt;
  std::exception_ptr error;
};

double call(unsigned n, const double* x, double* /*gradient: derivative-free methods pass none*/, void* data) {
  auto& s = *static_cast<Search*>(data);
  std::vector<double> point(x, x + n);
  for (double& v : point) v = std::clamp(v, 0.0, 1.0);  // NLopt keeps to the bounds; guard rounding anyway
  double value = std::numeric_limits<double>::max();
  try {
    value = s.f(point);
  } catch (...) {
    s.error = std::current_exception();
    nlopt_force_stop(s.opt);
    return value;
  }
  if (!std::isfinite(value)) value = std::numeric_limits<double>::max();
  ++s.out.evaluations;
  if (s.out.best_so_far.empty() || value < s.out.f) s.out.f = value, s.out.x = point;
  s.out.best_so_far.push_back(s.out.f);
  return value;
}

std::string stop_text(nlopt_result r) {
  switch (r) {
    case NLOPT_XTOL_REACHED: return "x tolerance";
    case NLOPT_FTOL_REACHED: return "f tolerance";
    case NLOPT_STOPVAL_REACHED: return "target value";
    case NLOPT_MAXEVAL_REACHED: return "evaluation budget";
    case NLOPT_ROUNDOFF_LIMITED: return "round-off";
    case NLOPT_SUCCESS: return "its own stopping test";  // BOBYQA: the trust region shrank to its end
    default: return fmt::format("NLopt result {}", static_cast<int>(r));
  }
}

}  // namespace

Minimum minimize(const std::function<double(const std::vector<double>&)>& f, std::vector<double> start,
                 const Budget& budget) {
  Minimum out;
  const unsigned d = static_cast<unsigned>(start.size());
  for (double& v : start) v = std::clamp(v, 0.0, 1.0);
  out.x = start;
  if (d == 0 || budget.max_evaluations < 1) {
    out.method = "none";
    out.stop = d == 0 ? "nothing to fit" : "evaluation budget";
    out.converged = d == 0;
    return out;
  }
  const nlopt_algorithm algorithm = d >= 2 ? NLOPT_LN_BOBYQA : NLOPT_LN_COBYLA;
  out.method = d >= 2 ? "BOBYQA" : "COBYLA";
  nlopt_opt opt = nlopt_create(algorithm, d);
  if (!opt) throw std::runtime_error("calibrate: NLopt could not create its optimiser (out of memory?)");
  struct Destroy {
    nlopt_opt o;
    ~Destroy() { nlopt_destroy(o); }
  } destroy{opt};
  const std::vector<double> lower(d, 0.0), upper(d, 1.0), step(d, budget.initial_step);
  nlopt_set_lower_bounds(opt, lower.data());
  nlopt_set_upper_bounds(opt, upper.data());
  nlopt_set_maxeval(opt, budget.max_evaluations);
  nlopt_set_xtol_abs1(opt, budget.x_tolerance);
  nlopt_set_initial_step(opt, step.data());
  Search search{f, out, opt, nullptr};
  nlopt_set_min_objective(opt, &call, &search);
  std::vector<double> x = start;
  double fx = 0;
  const nlopt_result r = nlopt_optimize(opt, x.data(), &fx);
  if (search.error) std::rethrow_exception(search.error);
  if (r < 0 && r != NLOPT_ROUNDOFF_LIMITED)
    throw std::runtime_error(fmt::format("calibrate: NLopt {} failed ({})", out.method,
                                         nlopt_get_errmsg(opt) ? nlopt_get_errmsg(opt) : stop_text(r)));
  out.stop = stop_text(r);
  out.converged = r != NLOPT_MAXEVAL_REACHED;
  return out;
}

}  // namespace aovar::calibrate
