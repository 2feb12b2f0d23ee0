// What the planner does when nothing toward the goal passed the trajectory check: short
// optimised detours, and the choice between braking, the plan being followed, the least-bad
// rejected plan and an evasive manoeuvre (evasion.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ucon/planner/evasion.hpp"
#include "ucon/planner/planner_node.hpp"

namespace ucon::planner {

namespace {
constexpr int64_t kUsPerS = 1000000;
}  // namespace

PlannerNode::Evasion PlannerNode::evade(int64_t now) {
  // Braking, the least-bad rejected plan and the fan of manoeuvres, by one score (evasion.hpp).
  const int64_t t0 = now + int64_t(params_.latency_s * kUsPerS);
  const trajopt::DistanceField2D* field = staticField();
  const Eigen::Vector2d goal_xy(goal_->x, goal_->y);
  const double r = params_.optimizer.robot_radius;
  const EvasionParams& ep = params_.evasion;
  Evasion out;
  trajectory::PiecewisePolynomial stop_pp;
  Eigen::Vector2d p, v;
  if (!stopPolynomial(now, &stop_pp) || !expectedState(now, &p, &v)) return out;
  const EvasionScore braking = scoreTrajectory(stop_pp, t0, goal_xy, field, obstacles_, r, ep);
  EvasionScore least_bad;
  least_bad.total = -std::numeric_limits<double>::infinity();
  if (fallback_) least_bad = scoreTrajectory(fallback_->pp, t0, goal_xy, field, obstacles_, r, ep);
  // The trajectory being followed (it failed the check, as everything did): kept unless another
  // scores better by keep_margin, so that the manoeuvre of the last cycle is not swapped for a
  // near tie (a heading the other way within the noise of the prediction).
  EvasionScore kept;
  kept.total = -std::numeric_limits<double>::infinity();
  if (current_.valid() && current_status_ == trajectory_t::STATUS_OK)
    kept = scoreTrajectory(current_, t0, goal_xy, field, obstacles_, r, ep);
  const Manoeuvre m = bestManoeuvre(t0, p, v, goal_xy, params_.optimizer.max_velocity,
                                    params_.optimizer.max_acceleration, field, obstacles_, r, ep);
  const double m_total = m.pp.valid() ? m.score.total : -std::numeric_limits<double>::infinity();
  char buf[200];
  const double margin = ep.keep_margin;
  if (kept.total > braking.total && kept.total + margin >= least_bad.total && kept.total + margin >= m_total) {
    report_.count("evasion_kept");
    std::snprintf(buf, sizeof(buf), "kept (evasion): gap %.2f m predicted, braking %.2f m", kept.min_gap,
                  braking.min_gap);
    out.kind = Evasion::kKeep;
    out.message = buf;
  } else if (m_total > braking.total && m_total > least_bad.total) {
    report_.count("evasive_manoeuvres");
    std::snprintf(buf, sizeof(buf), "evasive manoeuvre at (%.2f, %.2f) m/s: gap %.2f m predicted, braking %.2f m",
                  m.velocity.x(), m.velocity.y(), m.score.min_gap, braking.min_gap);
    out.kind = Evasion::kManoeuvre;
    out.pp = m.pp;
    out.message = buf;
  } else if (least_bad.total > braking.total) {
    report_.count("least_bad_plans");
    std::snprintf(buf, sizeof(buf), "least bad: gap %.2f m predicted, braking %.2f m", least_bad.min_gap,
                  braking.min_gap);
    out.kind = Evasion::kLeastBad;
    out.pp = fallback_->pp;
    out.message = buf;
  }
  return out;
}

trajopt::PlanOutput PlannerNode::planEscape(const StartState& start, trajopt::PlanRequest req, int* iterations) {
  // Score 16 directions by the smallest predicted gap to any obstacle body along a straight
  // run at cruise speed (constant-velocity prediction, 0.25 s steps over the run).
  const double L = params_.escape_distance;
  const double v = std::max(0.3, params_.front_end.guess_speed_ratio * params_.optimizer.max_velocity);
  const double run_s = L / v;
  struct Candidate {
    double score;
    int index;
    Eigen::Vector2d target;
  };
  std::vector<Candidate> cands;
  for (int k = 0; k < 16; ++k) {
    const double a = k * (2.0 * M_PI / 16.0);
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const Eigen::Vector2d target = start.p + L * dir;
    if (!segmentClear(map_, start.p, target, params_.front_end.hard_clearance)) continue;
    double worst = std::numeric_limits<double>::infinity();
    for (double t = 0.25; t <= run_s + 1e-9; t += 0.25) {
      const Eigen::Vector2d p = start.p + dir * (v * t);
      for (const auto& o : obstacles_) {
        const double dt = t + double(start.utime - o.utime) * 1e-6;
        const Eigen::Vector2d q(o.state(0) + o.state(3) * dt, o.state(1) + o.state(4) * dt);
        worst = std::min(worst, (p - q).norm() - o.radius);
      }
    }
    cands.push_back({worst, k, target});
  }
  std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
    return x.score != y.score ? x.score > y.score : x.index < y.index;  // deterministic ties
  });
  trajopt::PlanOutput best;
  best.status = trajopt::PlanStatus::kOptimiserFailed;
  const int n = std::min<int>(params_.escape_candidates, int(cands.size()));
  for (int i = 0; i < n; ++i) {
    const std::vector<Eigen::Vector2d> path{start.p, cands[i].target};
    const InitialGuess g = makeInitialGuess(path, L, start.v.norm(), v, params_.front_end.guess_accel_ratio *
                                                                            params_.optimizer.max_acceleration,
                                            params_.front_end);
    req.goal.setZero();
    req.goal.col(0) = g.end;
    req.inner_waypoints = g.waypoints;
    req.durations = g.durations;
    best = optimizer_.plan(req);
    considerFallback(best);
    *iterations += best.iterations;
    report_.count("escape_attempts");
    if (best.status == trajopt::PlanStatus::kOk) break;
  }
  return best;
}

void PlannerNode::considerFallback(const trajopt::PlanOutput& po) {
  if (po.status != trajopt::PlanStatus::kDynamicCollision) return;
  const auto& op = params_.optimizer;
  if (!(po.min_static_clearance >= op.robot_radius)) return;
  if (!(po.max_speed <= op.max_velocity * (1.0 + op.limit_tolerance)) ||
      !(po.max_acceleration <= op.max_acceleration * (1.0 + op.limit_tolerance)))
    return;
  Fallback f;
  if (trajectory::PiecewisePolynomial::fromMessage(po.trajectory, &f.pp) != trajectory::TrajectoryStatus::kOk) return;
  f.contact_s = firstContact(f.pp, po.trajectory.start_utime);
  f.gap = po.min_dynamic_clearance;
  if (!fallback_ || f.contact_s > fallback_->contact_s ||
      (f.contact_s == fallback_->contact_s && f.gap > fallback_->gap))
    fallback_ = std::move(f);
}

double PlannerNode::firstContact(const trajectory::PiecewisePolynomial& pp, int64_t from_utime) const {
  const auto& op = params_.optimizer;
  const int steps = static_cast<int>(std::ceil(op.check_horizon / op.check_step));
  for (int s = 0; s <= steps; ++s) {
    const double ts = s * op.check_step;
    const int64_t t = from_utime + static_cast<int64_t>(std::llround(ts * kUsPerS));
    const Eigen::Vector2d p = pp.sample(t).position.head<2>();  // clamped: at rest after the end
    for (const auto& o : obstacles_) {
      if (!o.state.allFinite() || !std::isfinite(o.radius)) continue;
      if (trajopt::predictedBodyGap(o, p, t) < op.robot_radius) return ts;
    }
  }
  return std::numeric_limits<double>::infinity();
}

bool PlannerNode::expectedState(int64_t now, Eigen::Vector2d* p_out, Eigen::Vector2d* v_out) const {
  // The current plan at now + latency if any (the pose if the robot is off it), else the pose.
  const int64_t t0 = now + int64_t(params_.latency_s * kUsPerS);
  Eigen::Vector2d p, v = Eigen::Vector2d::Zero();
  bool have = false;
  if (current_.valid()) {
    const auto s = current_.sample(t0);
    p = s.position.head<2>();
    v = s.velocity.head<2>();
    have = true;
    if (pose_ && (p - Eigen::Vector2d(pose_->x, pose_->y)).norm() > params_.replan_deviation) {
      p = Eigen::Vector2d(pose_->x, pose_->y);
      v = Eigen::Vector2d(pose_->vx, pose_->vy);
    }
  } else if (pose_) {
    p = Eigen::Vector2d(pose_->x, pose_->y);
    v = Eigen::Vector2d(pose_->vx, pose_->vy);
    have = true;
  }
  if (!have || !p.allFinite() || !v.allFinite()) return false;
  *p_out = p;
  *v_out = v;
  return true;
}

bool PlannerNode::stopPolynomial(int64_t now, trajectory::PiecewisePolynomial* out) const {
  const int64_t t0 = now + int64_t(params_.latency_s * kUsPerS);
  Eigen::Vector2d p, v;
  if (!expectedState(now, &p, &v)) return false;
  // Straight to rest at the full acceleration limit, along the current velocity (half the
  // distance of a smooth minimum-jerk stop, whose peak deceleration would be the limit), then
  // held for half a second. The step in acceleration is the base controller's to smooth.
  const double speed = v.norm();
  const double amax = params_.optimizer.max_acceleration;
  const double Tb = speed / amax;  // braking time
  std::vector<double> durations, coeffs;
  Eigen::Vector2d rest = p;
  if (Tb > 1e-3) {
    const Eigen::Vector2d decel = v * (amax / speed);
    durations.push_back(Tb);
    for (int d = 0; d < 2; ++d) coeffs.insert(coeffs.end(), {p(d), v(d), -0.5 * decel(d), 0.0, 0.0, 0.0});
    rest += v * (0.5 * Tb);
  }
  durations.push_back(0.5);
  for (int d = 0; d < 2; ++d) coeffs.insert(coeffs.end(), {rest(d), 0.0, 0.0, 0.0, 0.0, 0.0});
  return trajectory::PiecewisePolynomial::create(t0, 2, 6, durations, coeffs, out) == trajectory::TrajectoryStatus::kOk;
}

}  // namespace ucon::planner
