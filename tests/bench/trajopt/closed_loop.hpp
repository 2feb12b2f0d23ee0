#pragma once
// Closed-loop sanity experiment for tuning the optimiser (not the paper's Table II benchmark,
// which lives with the planner): a robot crosses a world like the paper's Sec. V-C benchmark (docs/reference.md §8),
// obstacles are observed with noise through common/kalman, the optimiser replans at 10 Hz,
// ideal tracking.

#include <string>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace trajopt_bench {

struct ClosedLoopResult {
  bool success = false;
  bool collision = false;
  bool timeout = false;
  double plan_ms_median = 0.0;
  int plans = 0;
  int failed_plans = 0;
  int fail_by_status[6] = {0, 0, 0, 0, 0, 0};
  double collision_time = -1.0;
  double time_s = 0.0;
};

/// One crossing from (2, 25) to (48, 25) with `n_dynamic` moving obstacles (seeded world).
/// `debug` prints failed plans and the collision.
ClosedLoopResult runClosedLoop(unsigned seed, int n_dynamic, const ucon::trajopt::OptimizerParams& params,
                               const ucon::kalman::KalmanParams& filter, bool debug);

}  // namespace trajopt_bench
