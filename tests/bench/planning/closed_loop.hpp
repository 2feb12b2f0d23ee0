#pragma once
/// @file closed_loop.hpp
/// One closed-loop run of the dynamic-obstacle benchmark (paper Sec. V-C, issue 5): the seeded
/// world `bench:<N_d>:<seed>`, moving obstacles observed as ground-truth centroids plus
/// Gaussian noise at 50 Hz through the constant-velocity Kalman filter, the PlannerNode at its
/// configured rate, the robot following the published trajectory ideally.
///
/// The static map is built directly from the world's static obstacles into the planner's own
/// EsdfMap (every leaf of the height band whose centre lies within half a cell of a footprint),
/// not by ray casting: the benchmark measures the trajectory optimisation, not mapping.

#include <cstdint>
#include <string>
#include <vector>

#include "ucon/planner/planner_params.hpp"

namespace ucon::bench {

struct RunConfig {
  std::string method = "sector";   ///< sector | no_uncertainty | fapp
  int n_dynamic = 50;
  uint64_t seed = 1;
  double timeout_s = 120.0;        ///< run ends unsuccessfully after this much simulated time [s]
  double observe_hz = 50.0;        ///< obstacle observation rate [Hz]
  double noise_std = 0.05;         ///< centroid noise (1 sigma, per axis) [m]; also the trackers' position_std
  /// The trackers that stand in for perception: constant-velocity Kalman filters updated with
  /// the noisy centroids (position only), their process noise that of the planner's
  /// prediction model (planner.yaml `prediction`).
  double tracker_velocity_std = 0.3;         ///< [m/s] (not used by position-only updates)
  double tracker_initial_velocity_std = 1.0; ///< velocity uncertainty of a new track [m/s]
  double warmup_s = 1.0;           ///< obstacles are tracked this long before the goal is sent [s]
  double goal_tolerance = 0.3;     ///< success radius around the goal [m]
  bool trace = false;              ///< print every plan that did not end OK (diagnosis)
};

struct RunResult {
  bool success = false;
  bool collision = false;
  bool timeout = false;
  std::string collision_with;      ///< "static" | "moving" | ""
  double time_s = 0.0;             ///< simulated time until success / collision / timeout [s]
  double path_length = 0.0;        ///< [m]
  double jerk_mean = 0.0;          ///< mean |p'''| over the executed trajectory [m/s^3]
  std::vector<double> plan_ms;     ///< total planning time of every plan that ran the optimiser [ms]
  std::vector<double> plan_cpu_ms;  ///< the same plans' thread CPU time (robust to a shared machine) [ms]
  std::vector<double> map_ms, front_end_ms, optimize_ms;  ///< the stages of those plans [ms]
  std::vector<int> iterations;     ///< optimiser evaluations of those plans
  int stops = 0;                   ///< stopping trajectories published
  std::string counters;            ///< the planner's notable counters, "name=value ..."
};

/// Runs one world with `params` (the obstacle model is overridden by `cfg.method`; robot
/// radius and limits come from the world). Deterministic in (params, cfg) apart from plan_ms.
RunResult runClosedLoop(const planner::PlannerParams& params, const RunConfig& cfg);

}  // namespace ucon::bench
