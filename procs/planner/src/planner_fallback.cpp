// The planner's fallback policy (fallback_policy.hpp) applied to a cycle in which no plan toward
// the goal passed the check: keep, evade or brake.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ucon/planner/fallback_policy.hpp"
#include "ucon/planner/planner_node.hpp"

namespace ucon::planner {

namespace {

using Clock = std::chrono::steady_clock;  // compute-time measurement only, never decisions
constexpr int64_t kUsPerS = 1000000;
constexpr double kNone = -std::numeric_limits<double>::infinity();  // score of a candidate that does not exist

}  // namespace

PlannerOutputs PlannerNode::fallBack(Cycle& cycle, const StartState& start, const trajopt::PlanOutput& rejected) {
  const std::string why =
      std::string(trajopt::toString(rejected.status)) + (rejected.message.empty() ? "" : ": " + rejected.message);
  // Keep: the plan being followed still passes the check.
  if (previousStillSafe(cycle)) return keep(cycle, "rejected: " + why, "kept previous plan; new one rejected: " + why);
  // Evade, checked: short detours away from the predicted obstacles, each put through the check.
  trajectory::PiecewisePolynomial detour;
  if (rejected.status != trajopt::PlanStatus::kInvalidInput && tryDetours(start, cycle, &detour)) {
    report_.count("evasive_plans");
    return follow(cycle, detour, "evasive detour: no checked plan toward the goal");
  }
  // Otherwise keep, evade or brake by the score.
  const int64_t now = cycle.now;
  const int64_t t0 = now + int64_t(params_.latency_s * kUsPerS);
  trajectory::PiecewisePolynomial stop_pp;
  Eigen::Vector2d p, v;
  if (!stopPolynomial(now, &stop_pp) || !expectedState(now, &p, &v))
    return stop(cycle, PlanResult::kStopNoFeasible, "no feasible trajectory: " + why);
  const FallbackParams& fp = params_.fallback;
  const FallbackScore braking = score(stop_pp, t0);
  // The least-bad rejected plan of this cycle.
  FallbackScore least_bad;
  least_bad.total = kNone;
  const trajectory::PiecewisePolynomial* least_bad_pp = nullptr;
  for (const auto& pp : rejected_) {
    const FallbackScore s = score(pp, t0);
    if (s.total > least_bad.total) least_bad = s, least_bad_pp = &pp;
  }
  // The trajectory being followed (it failed the check, as everything did): kept unless another
  // scores better by keep_margin, so that the manoeuvre of the last cycle is not swapped for a
  // near tie (a heading the other way within the noise of the prediction).
  FallbackScore kept;
  kept.total = kNone;
  if (current_.valid() && current_status_ == trajectory_t::STATUS_OK) kept = score(current_, t0);
  const Manoeuvre m = bestManoeuvre(t0, p, v, Eigen::Vector2d(goal_->x, goal_->y), params_.optimizer.max_velocity,
                                    params_.optimizer.max_acceleration, staticField(), obstacles_,
                                    params_.optimizer.robot_radius, fp);
  const double m_total = m.pp.valid() ? m.score.total : kNone;
  char buf[200];
  switch (chooseFallback(braking.total, kept.total, least_bad.total, m_total, fp.keep_margin)) {
    case FallbackChoice::kKeep:
      report_.count("evasion_kept");
      std::snprintf(buf, sizeof(buf), "kept (evasion): gap %.2f m predicted, braking %.2f m", kept.min_gap,
                    braking.min_gap);
      return keep(cycle, buf, buf);
    case FallbackChoice::kManoeuvre:
      report_.count("evasive_manoeuvres");
      std::snprintf(buf, sizeof(buf), "evasive manoeuvre at (%.2f, %.2f) m/s: gap %.2f m predicted, braking %.2f m",
                    m.velocity.x(), m.velocity.y(), m.score.min_gap, braking.min_gap);
      return follow(cycle, m.pp, buf);
    case FallbackChoice::kLeastBad:
      report_.count("least_bad_plans");
      std::snprintf(buf, sizeof(buf), "least bad: gap %.2f m predicted, braking %.2f m", least_bad.min_gap,
                    braking.min_gap);
      return follow(cycle, *least_bad_pp, buf);
    case FallbackChoice::kBrake:
      break;
  }
  return stop(cycle, PlanResult::kStopNoFeasible, "no feasible trajectory: " + why);
}

bool PlannerNode::holdIsHit(int64_t now) const {
  trajectory::PiecewisePolynomial hold;
  if (!stopPolynomial(now, &hold)) return false;
  return score(hold, now + int64_t(params_.latency_s * kUsPerS)).min_gap <= 0.0;
}

FallbackScore PlannerNode::score(const trajectory::PiecewisePolynomial& pp, int64_t from_utime) const {
  return scoreTrajectory(pp, from_utime, Eigen::Vector2d(goal_->x, goal_->y), staticField(), obstacles_,
                         params_.optimizer.robot_radius, params_.fallback);
}

bool PlannerNode::tryDetours(const StartState& start, Cycle& cycle, trajectory::PiecewisePolynomial* detour) {
  const FallbackParams& fp = params_.fallback;
  if (fp.detours <= 0) return false;
  const auto t0 = Clock::now();
  const double L = fp.detour_length;
  const double speed = std::max(0.3, params_.front_end.guess_speed_ratio * params_.optimizer.max_velocity);
  const double amax = params_.front_end.guess_accel_ratio * params_.optimizer.max_acceleration;
  // Headings by the score of a straight run along each at cruise speed; the optimiser's initial
  // guess is that straight line, so it must keep hard_clearance from the map.
  const std::vector<int> headings =
      rankHeadings(start.utime, start.p, start.v, Eigen::Vector2d(goal_->x, goal_->y), speed,
                   params_.optimizer.max_acceleration, staticField(), obstacles_, params_.optimizer.robot_radius, fp);
  trajopt::PlanRequest req = requestFrom(start);
  int tried = 0;
  bool passed = false;
  for (const int k : headings) {
    if (tried >= fp.detours) break;
    const Eigen::Vector2d target = start.p + L * heading(k, fp.directions);
    if (!segmentClear(map_, start.p, target, params_.front_end.hard_clearance)) continue;
    ++tried;
    const InitialGuess g = makeInitialGuess({start.p, target}, L, start.v.norm(), speed, amax, params_.front_end);
    req.goal.setZero();
    req.goal.col(0) = g.end;
    req.inner_waypoints = g.waypoints;
    req.durations = g.durations;
    const trajopt::PlanOutput po = optimizer_.plan(req);
    cycle.info.iterations += po.iterations;
    report_.count("escape_attempts");
    if (po.status == trajopt::PlanStatus::kOk &&
        trajectory::PiecewisePolynomial::fromMessage(po.trajectory, detour) == trajectory::TrajectoryStatus::kOk) {
      passed = true;
      break;
    }
    keepIfLeastBadCandidate(po);
  }
  cycle.info.optimize_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return passed;
}

void PlannerNode::keepIfLeastBadCandidate(const trajopt::PlanOutput& po) {
  if (po.status != trajopt::PlanStatus::kDynamicCollision) return;
  const auto& op = params_.optimizer;
  if (!(po.min_static_clearance >= op.robot_radius)) return;
  if (!(po.max_speed <= op.max_velocity * (1.0 + op.limit_tolerance)) ||
      !(po.max_acceleration <= op.max_acceleration * (1.0 + op.limit_tolerance)))
    return;
  trajectory::PiecewisePolynomial pp;
  if (trajectory::PiecewisePolynomial::fromMessage(po.trajectory, &pp) != trajectory::TrajectoryStatus::kOk) return;
  rejected_.push_back(std::move(pp));
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
