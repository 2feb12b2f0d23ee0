#pragma once
/// @file planner_params.hpp
/// Parameters of the planner process; deploy/config/planner.yaml maps one-to-one onto them.

#include <string>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/planner/esdf_map.hpp"
#include "ucon/planner/fallback_policy.hpp"
#include "ucon/planner/guide_path.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon {
class ConfigReader;
}

namespace ucon::planner {

/// Goals outside this rectangle are rejected (YAML section `workspace`) [m].
struct Workspace {
  double x_min = -100.0, x_max = 100.0, y_min = -100.0, y_max = 100.0;
  void read(ConfigReader& r);
  bool contains(double x, double y) const { return x >= x_min && x <= x_max && y >= y_min && y <= y_max; }
};

/// The planner's prediction of an obstacle's covariance to future times, Σ_i(t) of eqs. 6-7
/// (YAML section `prediction`): the constant-velocity model of eq. 3 with white-acceleration
/// process noise Q. Only Q matters here (the planner predicts, it does not filter); the
/// measurement model is perception's (perception.yaml `kalman`).
struct PredictionParams {
  /// Acceleration noise density in x and y [m^2/s^3], > 0. Lower than perception's filter
  /// (0.5), which must follow a mover's turns from one 20 ms frame to the next: predicted
  /// 2 s ahead, 0.5 grows a sector's radius by k sqrt(q t^3 / 3) = 2.3 m (0.1: 1.0 m) and
  /// boxes the robot in among dense movers.
  double accel_psd_xy = 0.1;
  double accel_psd_z = 0.05;  ///< the same in z [m^2/s^3], > 0 (the planner works in x-y)
  void read(ConfigReader& r);
  /// The Kalman model with this process noise (its measurement noise is not used by prediction).
  kalman::KalmanParams model() const;
};

/// How tracked objects become the optimiser's obstacles (YAML `objects`).
struct ObjectParams {
  double fallback_position_std = 0.5;  ///< replaces a NaN / non-PD position covariance (1 sigma) [m]
  double fallback_velocity_std = 1.0;  ///< replaces a NaN / non-PD velocity covariance (1 sigma) [m/s]
  double max_age_s = 0.5;              ///< objects older than this are not trusted: plan stops [s]
  double max_range = 12.0;             ///< objects farther from the robot are ignored [m]
  bool include_tentative = true;       ///< plan around tentative tracks as well
  /// Smallest body radius given to a track [m], >= 0: a box shrunk by partial views (one side,
  /// a few returns) is not the object's size (0 = the box's half diagonal as it is).
  double min_radius = 0.3;
  /// Confirmed tracks at least this fast clear the static map under their body (movers' points
  /// that leaked into PERCEPTION_STATIC are ghost obstacles) [m/s]; 0 = off.
  double clear_under_speed = 0.3;
  double clear_max_radius = 0.6;       ///< ... within at most this radius [m]
  /// ... and only map columns whose current run of static points began at most this long ago
  /// (a ghost the mover has just left; not structure it passes, nor columns without current
  /// points) [s]; 0 = any column.
  double clear_max_age = 2.0;
  void read(ConfigReader& r);
};

/// Everything the planner node needs.
struct PlannerParams {
  double rate_hz = 10.0;              ///< replanning rate [Hz], 0.5..100
  double latency_s = 0.03;            ///< plans start at now + this (expected compute + transport) [s]
  double horizon_length = 7.0;        ///< longest guide path handed to the optimiser [m]
  double replan_deviation = 0.5;      ///< robot farther than this from the trajectory: restart from the pose [m]
  double pose_timeout_s = 0.5;        ///< pose older than this: stop [s]
  /// Static frames are gathered and ray-inserted together at most this often [s], 0..1
  /// (0 = every frame). OctoMap's ray insertion dominates the planner's CPU at the LiDAR's
  /// 50 Hz; one insertion of five merged frames casts each repeated endpoint once.
  double static_insert_period_s = 0.1;
  double goal_default_tolerance = 0.3; ///< used when nav_goal_t.tolerance is not > 0 [m]
  int max_attempts = 3;               ///< optimiser runs per cycle before giving up (slower, then shorter guesses), 1..5
  double retry_speed_scale = 0.6;     ///< each retry's initial guess is this much slower, 0.1..1
  /// Nothing toward the goal passed the check: keep / evade / brake by one score (YAML `fallback`).
  FallbackParams fallback;
  Workspace workspace;
  ObjectParams objects;
  PredictionParams prediction;        ///< prediction model of obstacle covariance
  MapParams map;
  FrontEndParams front_end;
  /// Obstacle model (sector | no_uncertainty | fapp), robot radius and limits, weights,
  /// solver budget and the post-check live here (common/trajopt).
  trajopt::OptimizerParams optimizer;

  void read(ConfigReader& r);
};

}  // namespace ucon::planner
