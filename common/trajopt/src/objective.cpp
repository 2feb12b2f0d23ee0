#include "ucon/trajopt/objective.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ucon/minco/time_map.hpp"

namespace ucon::trajopt {

namespace {

// Distance between segments [a0, a1] and [b0, b1] in the plane.
double pointSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).norm();
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double segmentSegment(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1, const Eigen::Vector2d& b0,
                      const Eigen::Vector2d& b1) {
  const Eigen::Vector2d r = a1 - a0, s = b1 - b0;
  const double den = cross(r, s);
  if (std::abs(den) > 1e-12) {
    const double t = cross(b0 - a0, s) / den, u = cross(b0 - a0, r) / den;
    if (t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0) return 0.0;
  }
  return std::min(std::min(pointSegment(a0, b0, b1), pointSegment(a1, b0, b1)),
                  std::min(pointSegment(b0, a0, a1), pointSegment(b1, a0, a1)));
}

}  // namespace

SectorMincoObjective::SectorMincoObjective(const OptimizerParams& params,
                                           const kalman::KalmanParams& prediction)
    : params_(params), prediction_(prediction) {}

std::string SectorMincoObjective::setup(const PlanRequest& req) {
  const std::string bad = params_.validate();
  if (!bad.empty()) return "bad optimizer parameter '" + bad + "'";
  if (!prediction_.validate().empty()) return "bad prediction parameter '" + prediction_.validate() + "'";
  if (req.start_utime <= 0) return "start_utime must be > 0";
  if (!req.start.allFinite()) return "start state is not finite";
  if (!req.goal.allFinite()) return "goal state is not finite";
  const int n = static_cast<int>(req.durations.size());
  if (n < 1) return "no durations (need at least one piece)";
  if (static_cast<int>(req.inner_waypoints.size()) != n - 1)
    return "inner_waypoints must number durations - 1";
  for (double T : req.durations)
    if (!std::isfinite(T) || !(T > 0.0)) return "durations must be finite and > 0";
  for (const auto& q : req.inner_waypoints)
    if (!q.allFinite()) return "inner waypoint is not finite";

  field_ = req.field;
  samples_ = params_.samples_per_piece;
  if (!minco_.setConditions(req.start, req.goal, n)) return "bad boundary conditions";
  if (n != n_) {
    n_ = n;
    q_.resize(2, n - 1);
    g_inner_.resize(2, n - 1);
    T_.resize(n);
    dT_dtau_.resize(n);
    gT_.resize(n);
    gT_total_.resize(n);
    time_tail_.resize(n);
    gC_.resize(6 * n, 2);
    candidate_begin_.assign(n + 1, 0);
  }
  inner0_.resize(2, n - 1);
  for (int i = 0; i + 1 < n; ++i) inner0_.col(i) = req.inner_waypoints[i];
  T0_ = Eigen::Map<const Eigen::VectorXd>(req.durations.data(), n);

  // Obstacles: prepare, and drop those whose reach over the horizon stays farther than
  // obstacle_corridor from the initial path (start, waypoints, goal).
  tracks_.clear();
  rejected_ = 0;
  without_covariance_ = 0;
  std::vector<Eigen::Vector2d> path;
  path.reserve(n + 1);
  path.push_back(req.start.col(0));
  for (const auto& q : req.inner_waypoints) path.push_back(q);
  path.push_back(req.goal.col(0));
  for (const auto& obs : req.obstacles) {
    ObstacleTrack tr;
    bool cov_ok = true;
    if (!prepareObstacle(obs, req.start_utime, prediction_, params_, &tr, &cov_ok)) {
      ++rejected_;
      continue;
    }
    if (!cov_ok) ++without_covariance_;
    const Eigen::Vector2d c0 = tr.mu_ref + tr.vel * (0.0 - tr.t_ref);
    const Eigen::Vector2d c1 = tr.mu_ref + tr.vel * (params_.dynamic_horizon - tr.t_ref);
    double dmin = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < path.size(); ++k)
      dmin = std::min(dmin, segmentSegment(c0, c1, path[k], path[k + 1]));
    if (dmin <= tr.reach + params_.obstacle_corridor) tracks_.push_back(tr);
  }
  candidates_.reserve(tracks_.size() * static_cast<std::size_t>(n));
  return {};
}

Eigen::VectorXd SectorMincoObjective::initialGuess() const {
  Eigen::VectorXd x(dimension());
  for (int i = 0; i + 1 < n_; ++i) x.segment<2>(2 * i) = inner0_.col(i);
  for (int i = 0; i < n_; ++i) x(2 * (n_ - 1) + i) = minco::tauFromDuration(T0_(i));
  return x;
}

void SectorMincoObjective::decode(const double* x, std::vector<Eigen::Vector2d>* inner,
                                  std::vector<double>* durations) const {
  inner->resize(std::max(0, n_ - 1));
  durations->resize(n_);
  for (int i = 0; i + 1 < n_; ++i) (*inner)[i] = Eigen::Vector2d(x[2 * i], x[2 * i + 1]);
  for (int i = 0; i < n_; ++i) (*durations)[i] = minco::durationFromTau(x[2 * (n_ - 1) + i]);
}

double SectorMincoObjective::evaluate(const double* x, double* grad) {
  const int n = n_, L = samples_;
  const int m = 2 * (n - 1);
  for (int i = 0; i + 1 < n; ++i) q_.col(i) = Eigen::Vector2d(x[2 * i], x[2 * i + 1]);
  for (int i = 0; i < n; ++i) {
    T_(i) = minco::durationFromTau(x[m + i]);
    dT_dtau_(i) = minco::durationDerivative(x[m + i]);
  }
  breakdown_ = CostBreakdown();
  if (!minco_.setParameters(q_, T_)) {
    if (grad) std::fill(grad, grad + dimension(), 0.0);
    return 1e300;
  }
  gC_.setZero();
  gT_.setZero();
  breakdown_.energy = minco_.energy();
  minco_.addEnergyGradient(gC_, gT_);
  breakdown_.time = params_.rho * T_.sum();
  gT_.array() += params_.rho;

  const Eigen::MatrixXd& c = minco_.coeffs();
  const double horizon = params_.dynamic_horizon;

  // Per piece: the obstacles whose centre box over the piece's time span comes within their
  // reach of the box around the piece's samples (exact cull: skipped pairs would cost 0).
  candidates_.clear();
  double t_start = 0.0;
  for (int i = 0; i < n; ++i) {
    candidate_begin_[i] = static_cast<int>(candidates_.size());
    const double t_end = t_start + T_(i);
    if (!tracks_.empty() && t_start < horizon) {
      Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
      Eigen::Vector2d hi = -lo;
      for (int j = 0; j <= L; ++j) {
        const double t = T_(i) * j / L;
        Eigen::Vector2d p = c.row(6 * i + 5).transpose();
        for (int k = 4; k >= 0; --k) p = p * t + c.row(6 * i + k).transpose();
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      const double tb = std::min(t_end, horizon);
      for (int k = 0; k < static_cast<int>(tracks_.size()); ++k) {
        const ObstacleTrack& tr = tracks_[k];
        const Eigen::Vector2d a = tr.mu_ref + tr.vel * (t_start - tr.t_ref);
        const Eigen::Vector2d b = tr.mu_ref + tr.vel * (tb - tr.t_ref);
        const Eigen::Vector2d olo = a.cwiseMin(b), ohi = a.cwiseMax(b);
        const Eigen::Vector2d gap = (olo - hi).cwiseMax(lo - ohi).cwiseMax(0.0);
        if (gap.squaredNorm() <= tr.reach * tr.reach) candidates_.push_back(k);
      }
    }
    t_start = t_end;
  }
  candidate_begin_[n] = static_cast<int>(candidates_.size());

  // Sampled penalties with trapezoid weights ω_j = T_i/L · (1/2 at both ends, else 1).
  t_start = 0.0;
  for (int i = 0; i < n; ++i) {
    const double Ti = T_(i);
    double time_grad_sum = 0.0;  // Σ ω ∂g/∂t of this piece: moves with every earlier duration
    for (int j = 0; j <= L; ++j) {
      const double s = static_cast<double>(j) / L;
      const double t = s * Ti;
      const double omega = (j == 0 || j == L) ? 0.5 * Ti / L : Ti / L;
      // p, v, a, jerk by Horner.
      Eigen::Vector2d p = Eigen::Vector2d::Zero(), v = p, a = p, jr = p;
      for (int k = 5; k >= 0; --k) {
        const Eigen::Vector2d ck = c.row(6 * i + k).transpose();
        p = p * t + ck;
        if (k >= 1) v = v * t + k * ck;
        if (k >= 2) a = a * t + k * (k - 1) * ck;
        if (k >= 3) jr = jr * t + k * (k - 1) * (k - 2) * ck;
      }
      Eigen::Vector2d gp = Eigen::Vector2d::Zero(), gv = gp, ga = gp;
      double gt = 0.0;
      double g_static = 0.0, g_dyn = 0.0;
      if (field_) g_static = staticClearanceCost(*field_, p, params_.safe_distance, params_.weight_static, &gp);
      const double g_vel = limitCost(v, params_.max_velocity, params_.weight_velocity, &gv);
      const double g_acc = limitCost(a, params_.max_acceleration, params_.weight_acceleration, &ga);
      const double t_abs = t_start + t;
      if (t_abs < horizon && candidate_begin_[i] < candidate_begin_[i + 1]) {
        Eigen::Vector2d gpd = Eigen::Vector2d::Zero();
        double gtd = 0.0, jd = 0.0;
        for (int idx = candidate_begin_[i]; idx < candidate_begin_[i + 1]; ++idx)
          jd += dynamicObstacleCost(tracks_[candidates_[idx]], params_, p, t_abs, &gpd, &gtd);
        if (jd > 0.0 || gtd != 0.0) {
          double dw;
          const double w = horizonWeight(t_abs, horizon, &dw);
          g_dyn = params_.lambda_d * w * jd;
          gp += params_.lambda_d * w * gpd;
          gt += params_.lambda_d * (w * gtd + dw * jd);
        }
      }
      const double g = g_static + g_vel + g_acc + g_dyn;
      breakdown_.static_clearance += omega * g_static;
      breakdown_.velocity += omega * g_vel;
      breakdown_.acceleration += omega * g_acc;
      breakdown_.dynamic += omega * g_dyn;
      if (g == 0.0 && gp.isZero() && gv.isZero() && ga.isZero() && gt == 0.0) continue;
      // ∂/∂c: β(t) gpᵀ + β'(t) gvᵀ + β''(t) gaᵀ, weighted.
      double tp[6];
      tp[0] = 1.0;
      for (int k = 1; k < 6; ++k) tp[k] = tp[k - 1] * t;
      for (int k = 0; k < 6; ++k) {
        Eigen::Vector2d row = tp[k] * gp;
        if (k >= 1) row += k * tp[k - 1] * gv;
        if (k >= 2) row += k * (k - 1) * tp[k - 2] * ga;
        gC_.row(6 * i + k) += omega * row.transpose();
      }
      // ∂/∂T_i (explicit): ω/T_i · g + ω s (dg/dt along the piece + ∂g/∂t_abs), eq. (16) generalised.
      gT_(i) += omega / Ti * g + omega * s * (gp.dot(v) + gv.dot(a) + ga.dot(jr) + gt);
      time_grad_sum += omega * gt;
    }
    time_tail_(i) = time_grad_sum;
    t_start += Ti;
  }
  // Samples of piece i happen later when any earlier duration grows: ∂/∂T_k += Σ_{i>k}.
  double suffix = 0.0;
  for (int i = n - 1; i >= 0; --i) {
    gT_(i) += suffix;
    suffix += time_tail_(i);
  }

  const double total = breakdown_.total();
  if (grad) {
    minco_.propagateGradient(gC_, gT_, g_inner_, gT_total_);
    for (int i = 0; i + 1 < n; ++i) {
      grad[2 * i] = g_inner_(0, i);
      grad[2 * i + 1] = g_inner_(1, i);
    }
    for (int i = 0; i < n; ++i) grad[m + i] = gT_total_(i) * dT_dtau_(i);
  }
  return total;
}

}  // namespace ucon::trajopt
