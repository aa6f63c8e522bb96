#pragma once
// Bounded derivative-free minimisation over the unit box [0, 1]^d (callers map it onto parameter ranges),
// through NLopt: BOBYQA (Powell 2009) fits a quadratic model of f inside a trust region that stays within
// the bounds, so the smooth few-parameter objectives of calibration converge in tens of evaluations where
// a clamped Nelder-Mead kept hitting its cap. One parameter: NLopt's BOBYQA needs two, so 1-D fits use
// COBYLA (Powell 1994), also bounded and derivative-free.
#include <functional>
#include <string>
#include <vector>

namespace aovar::calibrate {

struct Budget {
  int max_evaluations = 60;
  double initial_step = 0.15;  // first trust-region radius, in units of the box
  double x_tolerance = 1e-3;   // stop when a step changes every coordinate by less than this
};

struct Minimum {
  std::vector<double> x;        // the best point evaluated (inside the box)
  double f = 0;                 // f(x)
  int evaluations = 0;          // calls of f, at most the budget
  bool converged = false;       // stopped by a tolerance, not by the budget
  std::string stop;             // why it stopped, in words ("x tolerance", "evaluation budget", ...)
  std::string method;           // "BOBYQA" / "COBYLA" (NLopt), or "none" for d = 0
  std::vector<double> best_so_far;  // after each evaluation: the lowest f so far (the convergence curve)
};

// Minimises f from `start` (clamped into the box). An exception thrown by f stops the search and is
// rethrown. Throws std::runtime_error when NLopt fails for another reason.
Minimum minimize(const std::function<double(const std::vector<double>&)>& f, std::vector<double> start,
                 const Budget& budget = {});

}  // namespace aovar::calibrate
