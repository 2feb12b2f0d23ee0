#include "ucon/trajopt/uncertainty_sector.hpp"

#include <algorithm>
#include <cmath>

namespace ucon::trajopt {

namespace {

constexpr double kDistEps2 = 1e-12;  // d = sqrt(|δ|^2 + eps^2): smooth at δ = 0

inline void sigmoid(double zeta, double z, double* value, double* derivative) {
  // σ_ζ(z) = 1/(1+exp(-ζz)), σ' = ζσ(1-σ) (paper eqs. 11 and 17).
  const double s = 1.0 / (1.0 + std::exp(-zeta * z));
  *value = s;
  *derivative = zeta * s * (1.0 - s);
}

inline double safeSqrt(double v) { return v > 1e-12 ? std::sqrt(v) : 0.0; }

}  // namespace

double dynamicCostCutoff(const OptimizerParams& params) {
  static const double kLog1e6 = std::log(1e6);  // once: the cost terms ask for it per sample
  return kLog1e6 / params.sector.alpha;
}

bool prepareObstacle(const PredictedObstacle& obs, int64_t plan_start_utime,
                     const kalman::KalmanParams& prediction, const OptimizerParams& params,
                     ObstacleTrack* out, bool* covariance_ok) {
  if (covariance_ok) *covariance_ok = true;
  if (!obs.state.allFinite() || !std::isfinite(obs.radius) || obs.radius < 0.0) return false;
  ObstacleTrack tr;
  tr.id = obs.id;
  tr.mu_ref = obs.state.head<2>();
  tr.vel = obs.state.segment<2>(3);
  tr.t_ref = 1e-6 * static_cast<double>(obs.utime - plan_start_utime);
  tr.radius = obs.radius;
  tr.speed = tr.vel.norm();
  tr.disk = !(tr.speed >= params.sector.min_speed) || tr.speed <= 0.0;
  if (!tr.disk) {
    tr.dir = tr.vel / tr.speed;
    tr.perp = Eigen::Vector2d(-tr.dir.y(), tr.dir.x());
  }
  for (auto& m : tr.S) m.setZero();
  if (params.obstacle_model == ObstacleModel::kSector) {
    if (obs.has_covariance && kalman::isSymmetricPositiveDefinite(obs.covariance) &&
        prediction.validate().empty()) {
      // Σ_i(t): x-y block of F(dt) P F(dt)^T + Q(dt), kept as its exact cubic in dt.
      const auto poly = kalman::covariancePolynomial(obs.covariance, prediction);
      for (int k = 0; k < 4; ++k) tr.S[k] = poly[k].topLeftCorner<2, 2>();
      tr.use_covariance = true;
    } else if (covariance_ok) {
      *covariance_ok = false;
    }
  }
  // Reach: bound on R_i(t) + cutoff over the plan window [0, dynamic_horizon].
  const double body = tr.radius + params.safe_distance;
  double radius_bound = body;
  if (params.obstacle_model == ObstacleModel::kFapp) {
    radius_bound = body + params.sector.fapp_margin;
  } else {
    radius_bound += tr.speed * params.sector.h;
    if (tr.use_covariance) {
      const double dt = std::max(0.0, params.dynamic_horizon - tr.t_ref);
      double trace_bound = 0.0, pw = 1.0;
      for (int k = 0; k < 4; ++k, pw *= dt) trace_bound += std::abs(tr.S[k].trace()) * pw;
      radius_bound += params.sector.k * std::sqrt(trace_bound);  // v̂ᵀΣv̂ <= tr Σ for PSD Σ
    }
  }
  tr.reach = radius_bound + dynamicCostCutoff(params);
  *out = tr;
  return true;
}

namespace {

// Σ_i(t) of a track (zero without covariance). Before the state's own time the covariance
// is held at its value (dt clamped at 0): predictions only go forward.
inline Eigen::Matrix2d covarianceAt(const ObstacleTrack& tr, double dt) {
  if (!tr.use_covariance) return Eigen::Matrix2d::Zero();
  const double tau = std::max(0.0, dt);
  return tr.S[0] + tau * (tr.S[1] + tau * (tr.S[2] + tau * tr.S[3]));
}

// dΣ_i/dt (zero without covariance, and before the state's own time).
inline Eigen::Matrix2d covarianceRateAt(const ObstacleTrack& tr, double dt) {
  if (!tr.use_covariance || !(dt > 0.0)) return Eigen::Matrix2d::Zero();
  return tr.S[1] + dt * (2.0 * tr.S[2] + 3.0 * dt * tr.S[3]);
}

}  // namespace

SectorShape sectorAt(const ObstacleTrack& tr, double t, const OptimizerParams& params) {
  const auto& sp = params.sector;
  const double dt = t - tr.t_ref;
  SectorShape s;
  s.centre = tr.mu_ref + tr.vel * dt;
  s.body_radius = tr.radius + params.safe_distance;
  if (params.obstacle_model == ObstacleModel::kFapp) {
    s.radius = s.body_radius + sp.fapp_margin;
    s.half_angle = M_PI;
    return s;
  }
  const Eigen::Matrix2d S = covarianceAt(tr, dt);
  if (tr.disk) {
    s.radius = s.body_radius + sp.k * safeSqrt(S.trace());
    s.half_angle = M_PI;
    return s;
  }
  s.radius = tr.speed * sp.h + sp.k * safeSqrt(tr.dir.dot(S * tr.dir)) + s.body_radius;  // eq. (6)
  s.half_angle = std::atan2(sp.kappa * safeSqrt(tr.perp.dot(S * tr.perp)), tr.speed * sp.h);  // eq. (7) / 2
  return s;
}

// One obstacle's term of J_d(p, t), paper eqs. (6)-(10), with these choices:
//  * Lateral term sign. As printed, l_i = cos(θ/2) - cos<δ, v> makes σ_β(l_i) large OUTSIDE the
//    cone, contradicting the text ("danger zone along the main direction of motion"). We use
//    l_i = cos<δ, v> - cos(θ/2), so σ_α(r_i)·σ_β(l_i) is high INSIDE the sector (d < R_i and
//    the angle to v below θ_i/2) and falls off laterally and behind the obstacle.
//  * Body. The obstacle's own footprint (radius r_i/2 + s) is dangerous in every direction,
//    which the sector alone does not cover (behind the obstacle σ_β -> 0). We add a body term:
//    J = σ_α(R_i - d) σ_β(l_i) + σ_α(r_i/2 + s - d), in [0, 2], smooth, equal to the paper's
//    term wherever the body term is 0. A sum, not a probabilistic union 1 - (1-a)(1-b): the
//    sigmoid saturates inside a large sector, and a union would then be flat (= 1) all the way
//    to the body, leaving no gradient that keeps the robot off the obstacle itself; in a
//    closed-loop trial (tests/bench/trajopt --closed-loop) the union collided far more often.
//  * |v| -> 0. Below min_speed the direction is undefined (and θ -> π): the sector becomes a
//    disk, σ_β := 1, with radius r_i/2 + s + k sqrt(tr Σ_i(t)) (tr Σ bounds the variance in
//    any direction, so the disk covers every possible heading).
//  * R_i'(t) and θ_i'(t) are analytic (Σ_i(t) is an exact cubic), not finite differences.
//  * no_uncertainty: Σ ≡ 0, so R_i = |v| h + r_i/2 + s and θ_i = 0 (the ablation).
//    fapp: a cylinder of fixed radius r_i/2 + s + fapp_margin, J = σ_α(radius - d).
double dynamicObstacleCost(const ObstacleTrack& tr, const OptimizerParams& params,
                           const Eigen::Vector2d& p, double t, Eigen::Vector2d* grad_p, double* grad_t) {
  const auto& sp = params.sector;
  const double dt = t - tr.t_ref;
  const Eigen::Vector2d delta = p - (tr.mu_ref + tr.vel * dt);  // δ_i(t)
  const double dist2 = delta.squaredNorm();
  if (dist2 > tr.reach * tr.reach) return 0.0;
  const double d = std::sqrt(dist2 + kDistEps2);
  const Eigen::Vector2d dd_dp = delta / d;        // ∂d/∂p
  const double dd_dt = -dd_dp.dot(tr.vel);        // ∂d/∂t (δ' = -v at fixed p)
  const double body = tr.radius + params.safe_distance;
  const double cutoff = dynamicCostCutoff(params);

  if (params.obstacle_model == ObstacleModel::kFapp) {
    const double R = body + sp.fapp_margin;
    if (d - R > cutoff) return 0.0;
    double A, dA;
    sigmoid(sp.alpha, R - d, &A, &dA);
    *grad_p -= dA * dd_dp;
    *grad_t -= dA * dd_dt;
    return A;
  }

  const Eigen::Matrix2d S = covarianceAt(tr, dt);
  Eigen::Matrix2d dS;  // only once the sample is known to be within reach
  double R, dR_dt;
  double B = 1.0;
  Eigen::Vector2d dB_dp = Eigen::Vector2d::Zero();
  double dB_dt = 0.0;
  if (tr.disk) {
    const double sd = safeSqrt(S.trace());
    R = body + sp.k * sd;
    if (d - R > cutoff) return 0.0;
    dS = covarianceRateAt(tr, dt);
    dR_dt = sd > 0.0 ? sp.k * dS.trace() / (2.0 * sd) : 0.0;
  } else {
    // Eq. (6): R = |v| h + k sqrt(v̂ᵀ Σ v̂) + r/2 + s.
    const double sv = safeSqrt(tr.dir.dot(S * tr.dir));
    R = tr.speed * sp.h + sp.k * sv + body;
    if (d - R > cutoff) return 0.0;  // about half the samples within reach end here
    dS = covarianceRateAt(tr, dt);
    dR_dt = sv > 0.0 ? sp.k * tr.dir.dot(dS * tr.dir) / (2.0 * sv) : 0.0;
    // Eq. (7): tan(θ/2) = κ sqrt(ûᵀ Σ û) / (|v| h) =: g; cos(θ/2) = 1/sqrt(1+g^2).
    const double su = safeSqrt(tr.perp.dot(S * tr.perp));
    const double vh = tr.speed * sp.h;
    double cos_half = 0.0, dcos_half = 0.0;
    if (vh > 0.0) {
      const double g = sp.kappa * su / vh;
      const double dg = su > 0.0 ? sp.kappa * tr.perp.dot(dS * tr.perp) / (2.0 * su * vh) : 0.0;
      const double q = 1.0 + g * g;
      cos_half = 1.0 / std::sqrt(q);
      dcos_half = -g * dg / (q * std::sqrt(q));
    }
    // cos<δ, v> and its partials (appendix eqs. 23-27 with v' = 0 under constant velocity).
    const double c = delta.dot(tr.dir) / d;
    const Eigen::Vector2d dc_dp = (tr.dir - c * dd_dp) / d;
    const double dc_dt = -dc_dp.dot(tr.vel);
    const double l = c - cos_half;  // sign chosen so that the cost is high INSIDE the cone
    double dB;
    sigmoid(sp.beta, l, &B, &dB);
    dB_dp = dB * dc_dp;
    dB_dt = dB * (dc_dt - dcos_half);
  }
  double A, dA;
  sigmoid(sp.alpha, R - d, &A, &dA);  // σ_α(r_i), r_i = R_i - d_i (eq. 8)
  const double a = A * B;
  const Eigen::Vector2d da_dp = -dA * B * dd_dp + A * dB_dp;
  const double da_dt = dA * B * (dR_dt - dd_dt) + A * dB_dt;
  double b, db;
  sigmoid(sp.alpha, body - d, &b, &db);
  const Eigen::Vector2d db_dp = -db * dd_dp;
  const double db_dt = -db * dd_dt;
  *grad_p += da_dp + db_dp;
  *grad_t += da_dt + db_dt;
  return a + b;
}

}  // namespace ucon::trajopt
