#pragma once
/// @file lbfgs.hpp
/// Minimises a smooth function with NLopt's LD_LBFGS. "Solvers don't know costs": the
/// adapter sees x, f(x) and ∇f(x) only; NLopt stays inside lbfgs_nlopt.cpp.

#include <functional>
#include <string>

#include <Eigen/Core>

namespace ucon::trajopt {

struct LbfgsOptions {
  int max_evaluations = 200;        ///< cap on objective evaluations, >= 1
  double relative_tolerance = 1e-5; ///< ftol_rel [-]
  int memory = 8;                   ///< L-BFGS history length
  /// Largest component of the first step [units of x]. L-BFGS starts with H0 = I, i.e. a step
  /// of -∇f, which for stiff penalties is huge; the objective is scaled by
  /// min(1, initial_step / |∇f(x0)|_inf) (same minimiser, scale-free stopping) to prevent it.
  double initial_step = 0.5;
  bool use_time_budget = false;     ///< wall-clock limit (non-deterministic: off in replay/tests)
  double time_budget_s = 0.005;     ///< [s]
};

struct LbfgsReport {
  bool ok = false;          ///< a finite best point exists (also after a budget stop)
  double f = 0.0;           ///< objective at the returned x
  int evaluations = 0;
  std::string result;       ///< NLopt's result code as text ("ftol_reached", "maxeval_reached", ...)
};

/// f(x, grad, n): returns f(x) and writes ∇f(x) to grad (n entries).
using ObjectiveFunction = std::function<double(const double* x, double* grad, int n)>;

/// Minimises f from x (in place). x becomes the best point seen by any evaluation.
LbfgsReport minimizeLbfgs(const ObjectiveFunction& f, Eigen::VectorXd& x, const LbfgsOptions& options);

}  // namespace ucon::trajopt
