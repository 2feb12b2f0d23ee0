#pragma once
/// @file uncertainty_sector.hpp
/// The uncertainty-aware sector of a moving obstacle and its collision cost (paper Sec. IV-B
/// and IV-C): the sector radius R_i(t) (eq. 6) and central angle θ_i(t) (eq. 7) from the
/// obstacle's predicted velocity and position covariance Σ_i(t), and the dynamic-obstacle
/// cost J_d(p, t) (eqs. 8-10, sigmoid eq. 11) with its analytic partial derivatives in p and t
/// (eqs. 17-22 and the appendix, eqs. 23-27). The departures from the paper, and why, are
/// listed beside dynamicObstacleCost in uncertainty_sector.cpp.

#include <cstdint>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon::trajopt {

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

/// The sector of a track at time t: centre μ_i(t), radius R_i(t) (eq. 6), half the central
/// angle θ_i(t) (eq. 7). For tests, visualisation and the documentation; the cost works the
/// same quantities out with their time derivatives.
struct SectorShape {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< μ_i(t) [m]
  double radius = 0.0;        ///< R_i(t) [m] (fapp: cylinder radius)
  double half_angle = 0.0;    ///< θ_i(t)/2 [rad] (π for a disk)
  double body_radius = 0.0;   ///< r_i/2 + s [m]
};
SectorShape sectorAt(const ObstacleTrack& track, double t, const OptimizerParams& params);

/// Distance beyond R_i(t) at which the sigmoid cost is cut to zero: σ_α(-cutoff) = 1e-6 [m].
double dynamicCostCutoff(const OptimizerParams& params);

/// One obstacle's term of J_d (eq. 10) at position p [m] and plan time t [s], in [0, 2]
/// (sector + body, without λ_d and without the horizon taper), with the choices documented
/// in the .cpp.
/// Adds dJ/dp to *grad_p and dJ/dt to *grad_t. Returns 0 without touching the gradients when
/// the robot is farther than R_i(t) + cutoff from μ_i(t).
double dynamicObstacleCost(const ObstacleTrack& track, const OptimizerParams& params,
                           const Eigen::Vector2d& p, double t, Eigen::Vector2d* grad_p, double* grad_t);

}  // namespace ucon::trajopt
