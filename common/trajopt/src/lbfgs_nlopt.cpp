// The one file that includes NLopt.
#include <cmath>
#include <limits>
#include <vector>

#include <nlopt.hpp>

#include "ucon/trajopt/lbfgs.hpp"

namespace ucon::trajopt {

namespace {

struct Context {
  const ObjectiveFunction* f;
  double scale;
  Eigen::VectorXd* best_x;
  double best_f;
  int evaluations;
  bool non_finite;
};

double callback(unsigned n, const double* x, double* grad, void* data) {
  auto* ctx = static_cast<Context*>(data);
  ++ctx->evaluations;
  thread_local std::vector<double> scratch;
  double* g = grad;
  if (!g) {
    scratch.resize(n);
    g = scratch.data();
  }
  const double f = (*ctx->f)(x, g, static_cast<int>(n));
  if (!std::isfinite(f)) {
    ctx->non_finite = true;
    return std::numeric_limits<double>::max();
  }
  if (f < ctx->best_f) {
    ctx->best_f = f;
    for (unsigned i = 0; i < n; ++i) (*ctx->best_x)(i) = x[i];
  }
  for (unsigned i = 0; i < n; ++i) g[i] *= ctx->scale;
  return f * ctx->scale;
}

const char* resultName(nlopt::result r) {
  switch (r) {
    case nlopt::FAILURE: return "failure";
    case nlopt::INVALID_ARGS: return "invalid_args";
    case nlopt::OUT_OF_MEMORY: return "out_of_memory";
    case nlopt::ROUNDOFF_LIMITED: return "roundoff_limited";
    case nlopt::FORCED_STOP: return "forced_stop";
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "stopval_reached";
    case nlopt::FTOL_REACHED: return "ftol_reached";
    case nlopt::XTOL_REACHED: return "xtol_reached";
    case nlopt::MAXEVAL_REACHED: return "maxeval_reached";
    case nlopt::MAXTIME_REACHED: return "maxtime_reached";
    default: return "unknown";
  }
}

}  // namespace

LbfgsReport minimizeLbfgs(const ObjectiveFunction& f, Eigen::VectorXd& x, const LbfgsOptions& options) {
  LbfgsReport report;
  const unsigned n = static_cast<unsigned>(x.size());
  if (n == 0 || !x.allFinite()) {
    report.result = "invalid_args";
    return report;
  }
  Eigen::VectorXd best = x;
  Context ctx{&f, 1.0, &best, std::numeric_limits<double>::infinity(), 0, false};
  {
    // First-step scaling (see LbfgsOptions::initial_step); this evaluation counts.
    Eigen::VectorXd g0(n);
    const double f0 = callback(n, x.data(), g0.data(), &ctx);
    const double gmax = g0.cwiseAbs().maxCoeff();
    if (!std::isfinite(f0) || ctx.non_finite || !std::isfinite(gmax)) {
      report.result = "non_finite_start";
      report.evaluations = ctx.evaluations;
      return report;
    }
    if (gmax > options.initial_step) ctx.scale = options.initial_step / gmax;
  }
  std::vector<double> xv(x.data(), x.data() + n);
  double fx = 0.0;
  nlopt::result result = nlopt::FAILURE;
  try {
    nlopt::opt opt(nlopt::LD_LBFGS, n);
    opt.set_min_objective(&callback, &ctx);
    opt.set_maxeval(std::max(1, options.max_evaluations - 1));
    opt.set_ftol_rel(options.relative_tolerance);
    opt.set_vector_storage(static_cast<unsigned>(std::max(1, options.memory)));
    if (options.use_time_budget) opt.set_maxtime(options.time_budget_s);
    result = opt.optimize(xv, fx);
  } catch (const nlopt::roundoff_limited&) {
    result = nlopt::ROUNDOFF_LIMITED;  // common near a flat optimum: keep the best point
  } catch (const nlopt::forced_stop&) {
    result = nlopt::FORCED_STOP;
  } catch (const std::invalid_argument&) {
    result = nlopt::INVALID_ARGS;
  } catch (const std::bad_alloc&) {
    result = nlopt::OUT_OF_MEMORY;
  } catch (const std::exception&) {
    result = nlopt::FAILURE;
  }
  report.result = resultName(result);
  report.evaluations = ctx.evaluations;
  if (std::isfinite(ctx.best_f)) {
    x = best;
    report.f = ctx.best_f;
    report.ok = result != nlopt::INVALID_ARGS && result != nlopt::OUT_OF_MEMORY;
  }
  return report;
}

}  // namespace ucon::trajopt
