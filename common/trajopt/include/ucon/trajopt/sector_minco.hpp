#pragma once
/// @file sector_minco.hpp
/// Sector-MINCO trajectory optimisation (paper Sec. IV-B..D): the planner's back end.
///
/// Given the start state at an absolute time, a goal state, an initial guess (inner waypoints
/// and durations from the guide path), the static distance field and the tracked moving
/// obstacles (state and 6x6 covariance at their own utime), optimises a 2-D minimum-jerk MINCO
/// trajectory with NLopt L-BFGS over J = energy + rho*sum(T) + penalties and checks the result
/// against static obstacles, limits and the predicted obstacles. Independent of maps and LCM.
/// Deterministic unless OptimizerParams::use_time_budget is set.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/tracked_object_t.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/trajopt/distance_field.hpp"

namespace ucon {
class ConfigReader;
}

namespace ucon::trajopt {

/// How moving obstacles enter the cost.
enum class ObstacleModel {
  kSector = 0,      ///< complete UCON: uncertainty sector (R_i, theta_i from the predicted covariance)
  kNoUncertainty,   ///< ablation: sector geometry without covariance terms
  kFapp,            ///< baseline: fixed-radius cylinder on the constant-velocity prediction
};
const char* toString(ObstacleModel m);  ///< "sector" | "no_uncertainty" | "fapp"
/// Parses the YAML spelling; false (and `out` unchanged) for an unknown name.
bool parseObstacleModel(const std::string& name, ObstacleModel* out);

/// Sector geometry and sigmoid parameters (YAML section `sector`), paper Sec. IV-B/C.
struct SectorParams {
  double h = 0.02;          ///< velocity term of the sector radius, R += |v| h [s], 0..10
  double k = 2.0;           ///< radial uncertainty multiplier, R += k sqrt(v^T Σ v) [-], 0..10
  double kappa = 0.05;      ///< lateral uncertainty gain of the central angle θ [-], 0..10
  double alpha = 15.0;      ///< radial sigmoid steepness σ_α [1/m], 0.1..1000
  double beta = 25.0;       ///< lateral sigmoid steepness σ_β [-], 0.1..1000
  double min_speed = 0.05;  ///< slower obstacles have no direction: a disk [m/s], 0..10
  double fapp_margin = 0.2; ///< fapp model: cylinder radius = radius + safe_distance + this [m], 0..5
  void read(ConfigReader& r);
};

/// Weights, limits and solver settings of the optimiser (YAML keys = field names).
struct OptimizerParams {
  ObstacleModel obstacle_model = ObstacleModel::kSector;  ///< key obstacle_model: sector | no_uncertainty | fapp
  double safe_distance = 0.4;    ///< s: required clearance Ξ(p) >= s, and body r_i/2 + s [m], 0..5
  double max_velocity = 1.5;     ///< v_1 [m/s], > 0
  double max_acceleration = 2.0; ///< v_2 [m/s^2], > 0
  double rho = 10.0;             ///< time regularisation ρ [1/s], >= 0
  double lambda_d = 5e3;         ///< dynamic-obstacle weight λ_d [-], >= 0
  double weight_static = 1e5;    ///< static clearance penalty weight (cubic in metres) [-], >= 0
  double weight_velocity = 1e3;  ///< velocity limit penalty weight (cubic in m^2/s^2) [-], >= 0
  double weight_acceleration = 1e3; ///< acceleration limit penalty weight (cubic in m^2/s^4) [-], >= 0
  int samples_per_piece = 12;    ///< L: penalty samples per piece are L + 1 (trapezoid), 2..100
  double dynamic_horizon = 2.0;  ///< moving obstacles cost nothing after this time from the start [s], > 0.5
  double obstacle_corridor = 3.0; ///< obstacles farther than this (plus their reach) from the initial path are dropped [m], >= 0
  int max_iterations = 200;      ///< cap on objective evaluations, 1..100000
  double relative_tolerance = 1e-5; ///< stop when J improves by less than this fraction, 0..1
  bool use_time_budget = false;  ///< wall-clock budget on the solver: OFF for replay and tests
  double time_budget_ms = 5.0;   ///< the budget when enabled [ms], > 0
  // Post-check of the result (hard geometric checks; the costs use safe_distance).
  double robot_radius = 0.3;     ///< robot disk radius for the collision checks [m], > 0, <= safe_distance
  double check_step = 0.02;      ///< sampling step of the post-check [s], > 0
  double check_horizon = 2.0;    ///< predicted obstacles are checked this far ahead [s], >= 0
  double limit_tolerance = 0.1;  ///< allowed relative excess of |v| and |a| in the check [-], >= 0
  /// In the check, each obstacle body grows by this many standard deviations of its predicted
  /// position (predictedPositionSigma) [-], >= 0 (0: the constant-velocity prediction as it is).
  double check_uncertainty_k = 1.0;
  /// ... by at most this much [m], >= 0 (0: no cap). A track seen only once states a velocity
  /// sigma of ~1 m/s, which grows its body by metres within the horizon and stalls the robot.
  double check_uncertainty_cap = 0.25;
  /// A trajectory starting closer to static obstacles than robot_radius (the map's cells are
  /// 0.1 m, and a mover's leaked points can land beside the robot) may stay that close for at
  /// most this long, never closer than it starts, on its way out [s], >= 0 (0: such a start
  /// fails the check, and the robot can only brake where it stands).
  double static_escape_s = 1.0;
  SectorParams sector;           ///< YAML section `sector`

  void read(ConfigReader& r);
  /// Empty when consistent, otherwise the key of the first bad field.
  std::string validate() const;
};

/// A tracked moving obstacle at its own time stamp, as perception publishes it.
struct PredictedObstacle {
  int64_t id = 0;
  int64_t utime = 0;               ///< time the state refers to [us]
  kalman::State6 state = kalman::State6::Zero();  ///< [x y z vx vy vz] [m, m/s]
  kalman::Cov6 covariance = kalman::Cov6::Identity(); ///< 6x6 over the state; ignored if !has_covariance
  bool has_covariance = true;      ///< false: the object is used without uncertainty terms
  double radius = 0.3;             ///< r_i/2: half the footprint diagonal [m], >= 0
};

/// One planning problem.
struct PlanRequest {
  int64_t start_utime = 0;         ///< absolute time of the start state [us], > 0
  Eigen::Matrix<double, 2, 3> start = Eigen::Matrix<double, 2, 3>::Zero();  ///< columns p [m], v [m/s], a [m/s^2]
  Eigen::Matrix<double, 2, 3> goal = Eigen::Matrix<double, 2, 3>::Zero();   ///< end state, same layout (usually v = a = 0)
  std::vector<Eigen::Vector2d> inner_waypoints;  ///< initial guess, N-1 points [m] (may be empty: one piece)
  std::vector<double> durations;   ///< initial guess, N durations [s], each > 0
  const DistanceField2D* field = nullptr;  ///< static map; null = no static obstacles
  std::vector<PredictedObstacle> obstacles;
};

/// Value of each term of J at the result.
struct CostBreakdown {
  double energy = 0.0;        ///< ∫||p'''||^2 [m^2/s^5]
  double time = 0.0;          ///< ρ ΣT
  double static_clearance = 0.0;
  double velocity = 0.0;
  double acceleration = 0.0;
  double dynamic = 0.0;       ///< λ_d ∫ J_d dt
  double total() const { return energy + time + static_clearance + velocity + acceleration + dynamic; }
};

enum class PlanStatus {
  kOk = 0,             ///< optimised and passed the post-check
  kInvalidInput,       ///< NaN, bad sizes, non-positive durations, bad params (see message)
  kOptimiserFailed,    ///< the solver could not produce a finite result
  kStaticCollision,    ///< result comes closer than robot_radius to a static obstacle
  kDynamicCollision,   ///< result meets a predicted obstacle body within check_horizon
  kLimitViolation,     ///< result exceeds the velocity / acceleration limits (with tolerance)
};
const char* toString(PlanStatus s);

/// Result of plan(). `trajectory` holds the optimised trajectory whenever one was computed
/// (also when the post-check failed; then trajectory.status = STATUS_INVALID), so a caller
/// may inspect it; publish it only when status == kOk.
struct PlanOutput {
  PlanStatus status = PlanStatus::kInvalidInput;
  std::string message;               ///< why, when status != kOk
  /// start_utime, dim = 2, order1 = 6, durations, coeffs, status (OK / INVALID), message,
  /// yaw = NaN filled; utime, seq, plan_id and goal_id are the caller's.
  trajectory_t trajectory;
  CostBreakdown cost;
  int iterations = 0;                ///< objective evaluations
  std::string solver_result;         ///< NLopt's result, for the status channel
  int obstacles_used = 0;            ///< obstacles that survived the corridor cull
  int obstacles_rejected = 0;        ///< non-finite state or radius: ignored
  int obstacles_without_covariance = 0; ///< covariance missing, NaN or not PD: used without it
  double min_static_clearance = 0.0; ///< min Ξ over the result [m] (+inf without a field)
  double min_dynamic_clearance = 0.0; ///< min distance to a predicted body surface within check_horizon [m]
  double max_speed = 0.0;            ///< [m/s]
  double max_acceleration = 0.0;     ///< [m/s^2]
  std::vector<Eigen::Vector2d> inner_waypoints;  ///< optimised (warm start of the next plan)
  std::vector<double> durations;     ///< optimised [s]
};

/// Post-check of any trajectory (e.g. the one being executed) from `from_utime` on.
struct SafetyCheck {
  PlanStatus status = PlanStatus::kOk;  ///< kOk, kStaticCollision, kDynamicCollision, kLimitViolation or kInvalidInput
  std::string message;
  double min_static_clearance = 0.0;    ///< [m]
  double min_dynamic_clearance = 0.0;   ///< [m]
  double max_speed = 0.0;               ///< [m/s]
  double max_acceleration = 0.0;        ///< [m/s^2]
};
/// Gap [m] between a point `p` and obstacle `o`'s body at time `utime` under the
/// constant-velocity prediction of its state (negative: inside the body); the post-check's test.
inline double predictedBodyGap(const PredictedObstacle& o, const Eigen::Vector2d& p, int64_t utime) {
  const double dt = 1e-6 * static_cast<double>(utime - o.utime);
  const Eigen::Vector2d mu = o.state.head<2>() + dt * o.state.segment<2>(3);
  return (p - mu).norm() - o.radius;
}

/// Standard deviation [m] of `o`'s predicted x-y position at `utime` along its most uncertain
/// direction, under constant velocity: sqrt(lambda_max(P_pp + dt (P_pv + P_vp) + dt^2 P_vv));
/// 0 without covariance or if that is not finite.
double predictedPositionSigma(const PredictedObstacle& o, int64_t utime);

/// `gap` (predictedBodyGap at `utime`) with the body grown by k standard deviations of its
/// predicted position (predictedPositionSigma), the growth at most `cap` [m] (cap <= 0: no
/// cap; k <= 0: no growth). Never above `gap`, and with a cap never below gap - cap.
inline double grownGap(double gap, const PredictedObstacle& o, int64_t utime, double k, double cap) {
  if (!(k > 0.0)) return gap;
  const double grow = k * predictedPositionSigma(o, utime);
  return gap - (cap > 0.0 ? std::min(grow, cap) : grow);
}

/// predictedBodyGap with the body grown as grownGap says.
inline double grownBodyGap(const PredictedObstacle& o, const Eigen::Vector2d& p, int64_t utime, double k,
                           double cap) {
  return grownGap(predictedBodyGap(o, p, utime), o, utime, k, cap);
}

/// Checks a 2-D order1 = 6 trajectory message against the field (may be null), the
/// obstacles (constant-velocity prediction of their state) and the limits of `params`.
/// Rejected obstacles (non-finite) are skipped. Deterministic.
SafetyCheck checkTrajectory(const trajectory_t& traj, int64_t from_utime, const DistanceField2D* field,
                            const std::vector<PredictedObstacle>& obstacles, const OptimizerParams& params);

/// Turns one PERCEPTION_OBJECTS entry into an obstacle at the message's `utime`
/// (radius = half the x-y footprint diagonal; cov_size != 36 -> has_covariance = false).
PredictedObstacle obstacleFromMessage(const tracked_object_t& obj, int64_t utime);

class SectorMincoObjective;

/// The optimiser. Holds buffers that are reused between plans (set up once per N).
class TrajectoryOptimizer {
 public:
  /// `prediction` is the Kalman model used to predict obstacle covariance to sample times
  /// (the same parameters as perception's filter).
  explicit TrajectoryOptimizer(const OptimizerParams& params = OptimizerParams(),
                               const kalman::KalmanParams& prediction = kalman::KalmanParams());
  ~TrajectoryOptimizer();
  TrajectoryOptimizer(const TrajectoryOptimizer&) = delete;
  TrajectoryOptimizer& operator=(const TrajectoryOptimizer&) = delete;

  const OptimizerParams& params() const { return params_; }
  /// Optimises one problem. Never throws; bad input gives kInvalidInput.
  PlanOutput plan(const PlanRequest& request);

 private:
  OptimizerParams params_;
  kalman::KalmanParams prediction_;
  std::unique_ptr<SectorMincoObjective> objective_;
};

}  // namespace ucon::trajopt
