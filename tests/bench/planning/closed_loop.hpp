#pragma once
/// @file closed_loop.hpp
/// One closed-loop run of the dynamic-obstacle benchmark (paper Sec. V-C, issue 5): the seeded
/// world `bench:<N_d>:<seed>`, moving obstacles observed as ground-truth centroids plus
/// Gaussian noise at 50 Hz through the constant-velocity Kalman filter (all of them, or only
/// those in line of sight: observation.hpp), the PlannerNode at its configured rate, the robot
/// following the published trajectory ideally. The open-loop protocol (issue 31) runs the same
/// loop as its reference policy and looks at the node's problem at probe times (`probe`).
///
/// The static map is built directly from the world's static obstacles into the planner's own
/// EsdfMap (every leaf of the height band whose centre lies within half a cell of a footprint),
/// not by ray casting: the benchmark measures the trajectory optimisation, not mapping.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "observation.hpp"
#include "ucon/planner/planner_node.hpp"
#include "ucon/planner/planner_params.hpp"

namespace ucon::bench {

/// What a probe sees: the node just before its tick at `utime` (pose and obstacles of this
/// frame delivered), the world at that time and the tracks.
struct ProbeContext {
  planner::PlannerNode& node;
  const world::World& world;
  const Observer& observer;
  double t = 0.0;             ///< world time [s]
  int64_t utime = 0;          ///< the node's time [us]
  Eigen::Vector2d robot = Eigen::Vector2d::Zero();
};

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
  ObserveMode observe = ObserveMode::kAll;   ///< all movers, or those in line of sight (observation.hpp)
  double sensing_range = 12.0;     ///< los: sensing range [m]
  double max_coast = 3.0;          ///< los: a hidden track is dropped after this (the Table II protocol's own value) [s]
  double coast_velocity_decay = 1.0;  ///< los: hidden tracks' velocity decay (perception.yaml tracks.coast_velocity_decay) [s]
  double warmup_s = 1.0;           ///< obstacles are tracked this long before the goal is sent [s]
  /// > 0: the robot shuttles (at the goal it is sent back to the start, and so on) and the run
  /// lasts this long after the warm-up, ending early only on a collision (open-loop protocol).
  double shuttle_s = 0.0;
  /// Called before the node's tick at probe_start_s after the goal was sent and every
  /// probe_period_s after that (null: no probes).
  std::function<void(const ProbeContext&)> probe;
  double probe_start_s = 3.0;      ///< [s]
  double probe_period_s = 1.0;     ///< [s]
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
  int goals_reached = 0;           ///< shuttle legs completed
  int64_t measurements = 0, coasting_frames = 0, tracks_started = 0;  ///< Observer statistics
  std::string counters;            ///< the planner's notable counters, "name=value ..."
};

/// The planner parameters of a run in world `sc`: obstacle model `method` (false if unknown),
/// robot radius, limits and workspace from the world, no wall-clock budget.
bool benchParams(const planner::PlannerParams& base, const world::Scenario& sc, const std::string& method,
                 planner::PlannerParams* out);

/// Runs one world with `params` (the obstacle model is overridden by `cfg.method`; robot
/// radius and limits come from the world). Deterministic in (params, cfg) apart from plan_ms.
RunResult runClosedLoop(const planner::PlannerParams& params, const RunConfig& cfg);

}  // namespace ucon::bench
