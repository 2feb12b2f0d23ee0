#include "ucon/trajopt/sector_minco.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ucon/config.hpp"
#include "ucon/trajopt/lbfgs.hpp"
#include "ucon/trajopt/objective.hpp"

namespace ucon::trajopt {

const char* toString(ObstacleModel m) {
  switch (m) {
    case ObstacleModel::kSector: return "sector";
    case ObstacleModel::kNoUncertainty: return "no_uncertainty";
    case ObstacleModel::kFapp: return "fapp";
  }
  return "unknown";
}

bool parseObstacleModel(const std::string& name, ObstacleModel* out) {
  for (ObstacleModel m : {ObstacleModel::kSector, ObstacleModel::kNoUncertainty, ObstacleModel::kFapp}) {
    if (name == toString(m)) {
      *out = m;
      return true;
    }
  }
  return false;
}

const char* toString(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk: return "ok";
    case PlanStatus::kInvalidInput: return "invalid_input";
    case PlanStatus::kOptimiserFailed: return "optimiser_failed";
    case PlanStatus::kStaticCollision: return "static_collision";
    case PlanStatus::kDynamicCollision: return "dynamic_collision";
    case PlanStatus::kLimitViolation: return "limit_violation";
  }
  return "unknown";
}

void SectorParams::read(ConfigReader& r) {
  r.read("h", h, 0.0, 10.0);
  r.read("k", k, 0.0, 10.0);
  r.read("kappa", kappa, 0.0, 10.0);
  r.read("alpha", alpha, 0.1, 1000.0);
  r.read("beta", beta, 0.1, 1000.0);
  r.read("min_speed", min_speed, 0.0, 10.0);
  r.read("fapp_margin", fapp_margin, 0.0, 5.0);
}

void OptimizerParams::read(ConfigReader& r) {
  std::string model = toString(obstacle_model);
  r.read("obstacle_model", model, {"sector", "no_uncertainty", "fapp"});
  parseObstacleModel(model, &obstacle_model);
  r.read("safe_distance", safe_distance, 0.0, 5.0);
  r.read("max_velocity", max_velocity, 1e-3, 100.0);
  r.read("max_acceleration", max_acceleration, 1e-3, 100.0);
  r.read("rho", rho, 0.0, 1e6);
  r.read("lambda_d", lambda_d, 0.0, 1e9);
  r.read("weight_static", weight_static, 0.0, 1e12);
  r.read("weight_velocity", weight_velocity, 0.0, 1e12);
  r.read("weight_acceleration", weight_acceleration, 0.0, 1e12);
  r.read("samples_per_piece", samples_per_piece, 2, 100);
  r.read("dynamic_horizon", dynamic_horizon, 0.5, 60.0);
  r.read("obstacle_corridor", obstacle_corridor, 0.0, 100.0);
  r.read("max_iterations", max_iterations, 1, 100000);
  r.read("relative_tolerance", relative_tolerance, 0.0, 1.0);
  r.read("use_time_budget", use_time_budget);
  r.read("time_budget_ms", time_budget_ms, 1e-3, 1e5);
  r.read("robot_radius", robot_radius, 1e-3, 5.0);
  r.read("check_step", check_step, 1e-3, 1.0);
  r.read("check_horizon", check_horizon, 0.0, 60.0);
  r.read("limit_tolerance", limit_tolerance, 0.0, 10.0);
  r.read("check_uncertainty_k", check_uncertainty_k, 0.0, 5.0);
  r.read("check_uncertainty_cap", check_uncertainty_cap, 0.0, 10.0);
  r.read("static_escape_s", static_escape_s, 0.0, 60.0);
  ConfigReader s = r.section("sector");
  sector.read(s);
  const std::string bad = validate();
  if (!bad.empty()) r.fail(bad, "inconsistent value (see OptimizerParams::validate)");
}

std::string OptimizerParams::validate() const {
  auto pos = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!nonneg(safe_distance)) return "safe_distance";
  if (!pos(max_velocity)) return "max_velocity";
  if (!pos(max_acceleration)) return "max_acceleration";
  if (!nonneg(rho)) return "rho";
  if (!nonneg(lambda_d)) return "lambda_d";
  if (!nonneg(weight_static)) return "weight_static";
  if (!nonneg(weight_velocity)) return "weight_velocity";
  if (!nonneg(weight_acceleration)) return "weight_acceleration";
  if (samples_per_piece < 2) return "samples_per_piece";
  if (!(std::isfinite(dynamic_horizon) && dynamic_horizon >= 0.5)) return "dynamic_horizon";
  if (!nonneg(obstacle_corridor)) return "obstacle_corridor";
  if (max_iterations < 1) return "max_iterations";
  if (!nonneg(relative_tolerance)) return "relative_tolerance";
  if (!pos(time_budget_ms)) return "time_budget_ms";
  if (!pos(robot_radius)) return "robot_radius";
  if (robot_radius > safe_distance) return "safe_distance";  // must cover the robot
  if (!pos(check_step)) return "check_step";
  if (!nonneg(check_horizon)) return "check_horizon";
  if (!nonneg(limit_tolerance)) return "limit_tolerance";
  if (!nonneg(check_uncertainty_k)) return "check_uncertainty_k";
  if (!nonneg(check_uncertainty_cap)) return "check_uncertainty_cap";
  if (!nonneg(static_escape_s)) return "static_escape_s";
  if (!nonneg(sector.h)) return "sector.h";
  if (!nonneg(sector.k)) return "sector.k";
  if (!nonneg(sector.kappa)) return "sector.kappa";
  if (!pos(sector.alpha)) return "sector.alpha";
  if (!pos(sector.beta)) return "sector.beta";
  if (!nonneg(sector.min_speed)) return "sector.min_speed";
  if (!nonneg(sector.fapp_margin)) return "sector.fapp_margin";
  return {};
}

PredictedObstacle obstacleFromMessage(const tracked_object_t& obj, int64_t utime) {
  PredictedObstacle o;
  o.id = obj.id;
  o.utime = utime;
  o.state << obj.x, obj.y, obj.z, obj.vx, obj.vy, obj.vz;
  o.radius = 0.5 * std::hypot(obj.size_x, obj.size_y);
  o.has_covariance = obj.cov_size == 36 && obj.cov.size() == 36;
  if (o.has_covariance)
    for (int i = 0; i < 36; ++i) o.covariance(i / 6, i % 6) = obj.cov[i];
  return o;
}

namespace {

// How much closer than its start a trajectory leaving the static clearance may come (the
// distance field is interpolated between 0.1 m cells; a path along a wall wobbles by this).
constexpr double kEscapeSlack = 0.01;  // [m]

// Evaluates derivative `order` (0..2) of a 2-D, order1 = 6 trajectory message at local time t of piece k.
Eigen::Vector2d evalPiece(const trajectory_t& tr, int k, double t, int order) {
  Eigen::Vector2d out;
  for (int d = 0; d < 2; ++d) {
    const double* c = &tr.coeffs[static_cast<std::size_t>((k * 2 + d) * 6)];
    double v = 0.0;
    for (int j = 5; j >= order; --j) {
      double f = 1.0;
      for (int r = 0; r < order; ++r) f *= (j - r);
      v = v * t + f * c[j];
    }
    out(d) = v;
  }
  return out;
}

}  // namespace

double predictedPositionSigma(const PredictedObstacle& o, int64_t utime) {
  if (!o.has_covariance) return 0.0;
  const double dt = 1e-6 * static_cast<double>(utime - o.utime);
  const auto& P = o.covariance;
  auto c = [&](int i, int j) { return P(i, j) + dt * (P(i, j + 3) + P(i + 3, j)) + dt * dt * P(i + 3, j + 3); };
  const double a = c(0, 0), b = 0.5 * (c(0, 1) + c(1, 0)), d = c(1, 1);
  const double l = 0.5 * (a + d) + std::sqrt(std::max(0.0, 0.25 * (a - d) * (a - d) + b * b));
  return std::isfinite(l) && l > 0.0 ? std::sqrt(l) : 0.0;
}

SafetyCheck checkTrajectory(const trajectory_t& tr, int64_t from_utime, const DistanceField2D* field,
                            const std::vector<PredictedObstacle>& obstacles, const OptimizerParams& params) {
  SafetyCheck out;
  out.min_static_clearance = std::numeric_limits<double>::infinity();
  out.min_dynamic_clearance = std::numeric_limits<double>::infinity();
  if (tr.dim != 2 || tr.order1 != 6 || tr.num_pieces < 1 ||
      static_cast<int>(tr.durations.size()) != tr.num_pieces ||
      static_cast<int>(tr.coeffs.size()) != tr.num_pieces * 12 || !params.validate().empty()) {
    out.status = PlanStatus::kInvalidInput;
    out.message = "trajectory is not 2-D quintic or parameters invalid";
    return out;
  }
  for (double T : tr.durations)
    if (!std::isfinite(T) || !(T > 0.0)) {
      out.status = PlanStatus::kInvalidInput;
      out.message = "non-positive duration";
      return out;
    }
  for (double c : tr.coeffs)
    if (!std::isfinite(c)) {
      out.status = PlanStatus::kInvalidInput;
      out.message = "non-finite coefficient";
      return out;
    }
  double total = 0.0;
  for (double T : tr.durations) total += T;
  const double t_from = std::clamp(1e-6 * static_cast<double>(from_utime - tr.start_utime), 0.0, total);
  const double vmax = params.max_velocity * (1.0 + params.limit_tolerance);
  const double amax = params.max_acceleration * (1.0 + params.limit_tolerance);
  const int steps = static_cast<int>(std::ceil((total - t_from) / params.check_step));
  int piece = 0;
  double piece_start = 0.0;
  double start_clearance = std::numeric_limits<double>::quiet_NaN();
  for (int s = 0; s <= steps; ++s) {
    const double t = std::min(total, t_from + s * params.check_step);
    while (piece + 1 < tr.num_pieces && t > piece_start + tr.durations[piece]) {
      piece_start += tr.durations[piece];
      ++piece;
    }
    const double tl = std::min(t - piece_start, tr.durations[piece]);
    const Eigen::Vector2d p = evalPiece(tr, piece, tl, 0);
    const double speed = evalPiece(tr, piece, tl, 1).norm();
    const double acc = evalPiece(tr, piece, tl, 2).norm();
    out.max_speed = std::max(out.max_speed, speed);
    out.max_acceleration = std::max(out.max_acceleration, acc);
    if (field) {
      const double xi = field->distance(p.x(), p.y(), nullptr);
      out.min_static_clearance = std::min(out.min_static_clearance, xi);
      if (s == 0) start_clearance = xi;
      // Starting inside the clearance: leaving it without coming closer is allowed for a while.
      const bool escaping = params.static_escape_s > 0.0 && start_clearance < params.robot_radius &&
                            t - t_from <= params.static_escape_s && xi >= start_clearance - kEscapeSlack;
      if (out.status == PlanStatus::kOk && xi < params.robot_radius && !escaping) {
        out.status = PlanStatus::kStaticCollision;
        out.message = "static clearance " + std::to_string(xi) + " m at t=" + std::to_string(t) + " s";
      }
    }
    if (t - t_from <= params.check_horizon) {
      const int64_t t_abs = tr.start_utime + static_cast<int64_t>(std::llround(t * 1e6));
      const double k = params.check_uncertainty_k, cap = params.check_uncertainty_cap;
      for (const auto& o : obstacles) {
        if (!o.state.allFinite() || !std::isfinite(o.radius)) continue;
        // grownBodyGap, its growth (the position's std, an eigenvalue) only worked out where it
        // can matter: the grown gap is at least gap0 - cap (rounding is monotone), so a body that
        // far cannot lower the minimum, nor fail the check (a minimum below the robot's radius
        // has failed it already).
        const double gap0 = predictedBodyGap(o, p, t_abs);
        if (k > 0.0 && cap > 0.0 && gap0 - cap >= out.min_dynamic_clearance) continue;
        const double gap = grownGap(gap0, o, t_abs, k, cap);
        out.min_dynamic_clearance = std::min(out.min_dynamic_clearance, gap);
        if (out.status == PlanStatus::kOk && gap < params.robot_radius) {
          out.status = PlanStatus::kDynamicCollision;
          out.message = "obstacle " + std::to_string(o.id) + " within " + std::to_string(gap) +
                        " m at t=" + std::to_string(t) + " s";
        }
      }
    }
    if (out.status == PlanStatus::kOk && (speed > vmax || acc > amax)) {
      out.status = PlanStatus::kLimitViolation;
      out.message = "speed " + std::to_string(speed) + " m/s, acceleration " + std::to_string(acc) +
                    " m/s^2 at t=" + std::to_string(t) + " s";
    }
  }
  return out;
}

TrajectoryOptimizer::TrajectoryOptimizer(const OptimizerParams& params, const kalman::KalmanParams& prediction)
    : params_(params), prediction_(prediction),
      objective_(std::make_unique<SectorMincoObjective>(params, prediction)) {}

TrajectoryOptimizer::~TrajectoryOptimizer() = default;

PlanOutput TrajectoryOptimizer::plan(const PlanRequest& request) {
  PlanOutput out;
  out.trajectory.utime = 0;
  out.trajectory.seq = 0;
  out.trajectory.plan_id = 0;
  out.trajectory.goal_id = 0;
  out.trajectory.status = trajectory_t::STATUS_INVALID;
  out.trajectory.start_utime = request.start_utime;
  out.trajectory.dim = 2;
  out.trajectory.order1 = 6;
  out.trajectory.num_pieces = 0;
  out.trajectory.num_coeffs = 0;
  out.trajectory.yaw = std::numeric_limits<double>::quiet_NaN();
  const std::string problem = objective_->setup(request);
  if (!problem.empty()) {
    out.status = PlanStatus::kInvalidInput;
    out.message = problem;
    out.trajectory.message = problem;
    return out;
  }
  out.obstacles_used = static_cast<int>(objective_->tracks().size());
  out.obstacles_rejected = objective_->obstaclesRejected();
  out.obstacles_without_covariance = objective_->obstaclesWithoutCovariance();

  Eigen::VectorXd x = objective_->initialGuess();
  LbfgsOptions options;
  options.max_evaluations = params_.max_iterations;
  options.relative_tolerance = params_.relative_tolerance;
  options.use_time_budget = params_.use_time_budget;
  options.time_budget_s = 1e-3 * params_.time_budget_ms;
  SectorMincoObjective* obj = objective_.get();
  const LbfgsReport rep = minimizeLbfgs(
      [obj](const double* xx, double* g, int) { return obj->evaluate(xx, g); }, x, options);
  out.iterations = rep.evaluations;
  out.solver_result = rep.result;
  // Re-evaluate at the best point so MINCO and the breakdown describe the result.
  const double f = obj->evaluate(x.data(), nullptr);
  if (!rep.ok || !std::isfinite(f) || f >= 1e300) {
    out.status = PlanStatus::kOptimiserFailed;
    out.message = "solver: " + rep.result;
    out.trajectory.message = out.message;
    return out;
  }
  out.cost = obj->breakdown();
  obj->decode(x.data(), &out.inner_waypoints, &out.durations);
  obj->trajectory().toTrajectory(request.start_utime, &out.trajectory);

  const SafetyCheck check = checkTrajectory(out.trajectory, request.start_utime, request.field,
                                            request.obstacles, params_);
  out.min_static_clearance = check.min_static_clearance;
  out.min_dynamic_clearance = check.min_dynamic_clearance;
  out.max_speed = check.max_speed;
  out.max_acceleration = check.max_acceleration;
  out.status = check.status;
  out.message = check.message;
  out.trajectory.status = out.status == PlanStatus::kOk ? trajectory_t::STATUS_OK : trajectory_t::STATUS_INVALID;
  out.trajectory.message = out.status == PlanStatus::kOk ? std::string() : std::string(toString(out.status)) + ": " + out.message;
  return out;
}

}  // namespace ucon::trajopt
