#pragma once
/// @file cost_terms.hpp
/// The terms of the sector-MINCO objective evaluated at one sample, each with its value and
/// analytic partial derivatives with respect to the sample's position p, velocity v,
/// acceleration a and plan-relative time t. The objective integrates them over each piece
/// with the paper's trapezoid weights.

#include <cstdint>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/trajopt/distance_field.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon::trajopt {

/// Static clearance (constraint Ξ(p) >= s): weight * max(0, s - Ξ(p))^3 (C^2 at the boundary).
/// Adds dC/dp to *grad_p.
double staticClearanceCost(const DistanceField2D& field, const Eigen::Vector2d& p, double safe_distance,
                           double weight, Eigen::Vector2d* grad_p);

/// Limit penalty for ||x|| <= limit (velocity or acceleration): weight * max(0, ||x||^2 - limit^2)^3.
/// Adds dC/dx to *grad_x.
double limitCost(const Eigen::Vector2d& x, double limit, double weight, Eigen::Vector2d* grad_x);

/// A moving obstacle prepared for repeated evaluation at plan-relative times t [s]:
/// mean mu(t) = mu_ref + vel (t - t_ref) and the x-y block of the Kalman-predicted covariance
/// Σ(t) = S0 + S1 dt + S2 dt^2 + S3 dt^3 with dt = max(0, t - t_ref) (common/kalman's closed form).
struct ObstacleTrack {
  int64_t id = 0;
  Eigen::Vector2d mu_ref = Eigen::Vector2d::Zero();  ///< x-y position at t_ref [m]
  Eigen::Vector2d vel = Eigen::Vector2d::Zero();     ///< x-y velocity [m/s]
  double t_ref = 0.0;             ///< time of the state relative to the plan start [s]
  Eigen::Matrix2d S[4];           ///< covariance polynomial (zero when !use_covariance)
  bool use_covariance = false;    ///< false for no_uncertainty / fapp and for bad covariances
  double radius = 0.0;            ///< r_i / 2 [m]
  double speed = 0.0;             ///< ||vel|| [m/s]
  Eigen::Vector2d dir = Eigen::Vector2d::UnitX();   ///< v̂ (unit; arbitrary when disk)
  Eigen::Vector2d perp = Eigen::Vector2d::UnitY();  ///< û, v̂ turned by +90°
  bool disk = false;              ///< speed < min_speed: no direction
  double reach = 0.0;             ///< bound on R(t) + cost cutoff over [0, dynamic_horizon] [m]
};

/// Builds the track of `obs` for a plan starting at `plan_start_utime`. Returns false when
/// the obstacle is unusable (non-finite state or radius). `covariance_ok` (optional) is set
/// false when the model wants a covariance but it is missing, non-finite or not PD (the
/// obstacle is then used without uncertainty terms).
bool prepareObstacle(const PredictedObstacle& obs, int64_t plan_start_utime,
                     const kalman::KalmanParams& prediction, const OptimizerParams& params,
                     ObstacleTrack* out, bool* covariance_ok);

/// The sector of a track at time t (for tests, visualisation and the documentation).
struct SectorShape {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< μ_i(t) [m]
  double radius = 0.0;        ///< R_i(t) [m] (fapp: cylinder radius)
  double half_angle = 0.0;    ///< θ_i(t)/2 [rad] (π for a disk)
  double body_radius = 0.0;   ///< r_i/2 + s [m]
};
SectorShape sectorAt(const ObstacleTrack& track, double t, const OptimizerParams& params);

/// Distance beyond R_i(t) at which the sigmoid cost is cut to zero: σ_α(-cutoff) = 1e-6 [m].
double dynamicCostCutoff(const OptimizerParams& params);

/// Smooth taper of the dynamic cost near the horizon: 1 until horizon - 0.5 s, smoothstep
/// to 0 at the horizon. Writes dw/dt to *dw.
double horizonWeight(double t, double horizon, double* dw);

/// Collision cost J_i(p, t) in [0, 2] (sector + body) of one obstacle at plan time t [s] (without
/// λ_d and without the horizon taper), paper eq. (10) with the choices documented in the .cpp.
/// Adds dJ/dp to *grad_p and dJ/dt to *grad_t. Returns 0 without touching the gradients when
/// the robot is farther than R_i(t) + cutoff from μ_i(t).
double dynamicObstacleCost(const ObstacleTrack& track, const OptimizerParams& params,
                           const Eigen::Vector2d& p, double t, Eigen::Vector2d* grad_p, double* grad_t);

}  // namespace ucon::trajopt
