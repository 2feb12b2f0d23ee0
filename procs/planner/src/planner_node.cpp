#include "ucon/planner/planner_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

namespace ucon::planner {

namespace {

using Clock = std::chrono::steady_clock;  // compute-time measurement only, never decisions
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool finite(double a, double b) { return std::isfinite(a) && std::isfinite(b); }

constexpr int64_t kUsPerS = 1000000;

}  // namespace

/// The ESDF slice as the optimiser's distance field.
class PlannerNode::Field : public trajopt::DistanceField2D {
 public:
  explicit Field(const EsdfMap& map) : map_(map) {}
  double distance(double x, double y, Eigen::Vector2d* grad) const override {
    return map_.distance(x, y, grad);
  }

 private:
  const EsdfMap& map_;
};

PlannerNode::PlannerNode(const PlannerParams& params, StatusReport& report)
    : params_(params),
      report_(report),
      map_(params.map),
      // Gaps up to 0.5 s (a return missing for a few frames) keep a run going; 512 cells of
      // one leaf span more than the map's range around the robot twice over.
      static_age_(params.map.resolution, 0.5, 512),
      field_(std::make_unique<Field>(map_)),
      optimizer_(params.optimizer, params.prediction.model()) {}

PlannerNode::~PlannerNode() = default;

void PlannerNode::onPose(const robot_pose_t& msg) {
  report_.count("pose_in");
  if (!msg.valid || msg.utime <= 0 || !finite(msg.x, msg.y) || !finite(msg.vx, msg.vy)) {
    report_.count("pose_rejected");
    return;
  }
  if (clock_.observe(msg.utime) == MessageClock::Observation::kOlder) {
    report_.count("pose_out_of_order");
    return;
  }
  pose_ = msg;
}

void PlannerNode::onObjects(const tracked_objects_t& msg) {
  report_.count("objects_msgs_in");
  if (!msg.valid || msg.utime <= 0 || msg.num_objects < 0 ||
      msg.objects.size() != std::size_t(msg.num_objects)) {
    // Not trusted: the previous obstacles age out and the planner stops (safety first).
    report_.count("objects_msgs_rejected");
    // A well-formed message marked invalid (perception without a fresh pose) still tells the
    // time: without it a planner whose pose stopped would have no "now" to see that by.
    if (!msg.valid && msg.utime > 0 && msg.num_objects >= 0 &&
        msg.objects.size() == std::size_t(msg.num_objects)) {
      clock_.observe(msg.utime);
    }
    return;
  }
  // Object frames carry their LiDAR frame's time, which is older than the poses that arrive
  // meanwhile (100 Hz): order is judged against the previous objects message only.
  if (objects_seen_ && msg.utime < objects_utime_) {
    report_.count("objects_out_of_order");
    return;
  }
  clock_.observe(msg.utime);
  obstacles_.clear();
  const ObjectParams& op = params_.objects;
  for (const auto& o : msg.objects) {
    if (o.state == tracked_object_t::STATE_DELETED) continue;
    if (o.state == tracked_object_t::STATE_TENTATIVE && !op.include_tentative) continue;
    if (!finite(o.x, o.y) || !finite(o.vx, o.vy)) {
      report_.count("objects_nan_dropped");
      continue;
    }
    trajopt::PredictedObstacle ob;
    ob.id = o.id;
    ob.utime = msg.utime;
    ob.has_covariance = true;
    ob.state << o.x, o.y, std::isfinite(o.z) ? o.z : 0.0, o.vx, o.vy, std::isfinite(o.vz) ? o.vz : 0.0;
    bool cov_ok = false;
    if (o.cov_size == 36 && o.cov.size() == 36) {
      for (int i = 0; i < 36; ++i) ob.covariance(i / 6, i % 6) = o.cov[i];
      cov_ok = kalman::isSymmetricPositiveDefinite(ob.covariance);
    }
    if (!cov_ok) {
      // A bad covariance does not make the object go away: plan around it with a wide,
      // conservative one instead and say so on the status.
      report_.count("objects_bad_covariance");
      const double ps = op.fallback_position_std * op.fallback_position_std;
      const double vs = op.fallback_velocity_std * op.fallback_velocity_std;
      ob.covariance = kalman::Cov6::Zero();
      ob.covariance.diagonal() << ps, ps, ps, vs, vs, vs;
    }
    const double diag = std::hypot(o.size_x, o.size_y);
    if (std::isfinite(diag) && diag > 0.0 && diag < 20.0) {
      ob.radius = std::max(0.5 * diag, op.min_radius);
    } else {
      report_.count("objects_bad_size");
      ob.radius = 0.5;
    }
    if (pose_ && std::hypot(o.x - pose_->x, o.y - pose_->y) > op.max_range) continue;
    obstacles_.push_back(ob);
    if (op.clear_under_speed > 0.0 && o.state == tracked_object_t::STATE_CONFIRMED &&
        std::hypot(o.vx, o.vy) >= op.clear_under_speed && std::isfinite(diag)) {
      // Structure the mover passes has had points for long; its own leaked points are new.
      // Columns with no current static points (occluded, e.g. by the mover) are left too.
      const int64_t max_age_us = int64_t(std::llround(op.clear_max_age * kUsPerS));
      const auto keep = [&](double cx, double cy) {
        const int64_t since = static_age_.occupiedSince(cx, cy, msg.utime);
        return since == CellAge::kNever || msg.utime - since > max_age_us;
      };
      map_.addCylinder(o.x, o.y, std::min(op.clear_max_radius, 0.5 * std::max(o.size_x, o.size_y)), false,
                       op.clear_max_age > 0.0 ? std::function<bool(double, double)>(keep) : nullptr);
      map_dirty_ = true;
      report_.count("cleared_under_movers");
    }
  }
  objects_utime_ = msg.utime;
  objects_seen_ = true;
  report_.set("obstacles", double(obstacles_.size()));
}

void PlannerNode::onStatic(const static_points_t& msg) {
  report_.count("static_in");
  if (!msg.valid || msg.utime <= 0 || msg.num_points < 0 ||
      msg.x.size() != std::size_t(msg.num_points) || msg.y.size() != std::size_t(msg.num_points) ||
      msg.z.size() != std::size_t(msg.num_points) ||
      !std::isfinite(msg.origin_x) || !std::isfinite(msg.origin_y) || !std::isfinite(msg.origin_z)) {
    report_.count("static_rejected");
    return;
  }
  int64_t nan = 0;
  for (int i = 0; i < msg.num_points; ++i) {
    const Eigen::Vector3f p(msg.x[i], msg.y[i], msg.z[i]);
    if (p.allFinite()) {
      pending_points_.push_back(p);
      if (p.z() >= params_.map.band_z_min && p.z() <= params_.map.band_z_max) static_age_.hit(msg.utime, p.x(), p.y());
    } else {
      ++nan;
    }
  }
  if (nan > 0) report_.count("static_points_nan", nan);
  // Rays of the merged frames start at the newest origin (the robot moves ~15 cm in 0.1 s).
  pending_origin_ = Eigen::Vector3d(msg.origin_x, msg.origin_y, msg.origin_z);
  pending_range_ = (std::isfinite(msg.max_range) && msg.max_range > 0.0f) ? double(msg.max_range) : 0.0;
  clock_.observe(msg.utime);
  ++static_frames_;
  if (last_insert_utime_ == 0 ||
      msg.utime - last_insert_utime_ >= int64_t(std::llround(params_.static_insert_period_s * kUsPerS))) {
    last_insert_utime_ = msg.utime;
    flushStaticPoints();
  }
}

void PlannerNode::flushStaticPoints() {
  if (pending_points_.empty()) return;
  const InsertStatus st = map_.insert(pending_origin_, pending_points_, pending_range_);
  pending_points_.clear();
  if (st != InsertStatus::kOk) {
    report_.count("static_rejected");
    return;
  }
  report_.count("static_insertions");
  map_dirty_ = true;
  map_received_ = true;
}

void PlannerNode::onGoal(const nav_goal_t& msg) {
  report_.count("goals_in");
  if (msg.action == nav_goal_t::ACTION_CANCEL) {
    goal_.reset();
    cancel_pending_ = true;
    pending_message_ = "goal cancelled";
    return;
  }
  std::string why;
  if (msg.action != nav_goal_t::ACTION_GO) {
    why = "unknown goal action " + std::to_string(int(msg.action));
  } else if (!finite(msg.x, msg.y)) {
    why = "goal position is not finite";
  } else if (!params_.workspace.contains(msg.x, msg.y)) {
    why = "goal outside the map (workspace x[" + std::to_string(params_.workspace.x_min) + ", " +
          std::to_string(params_.workspace.x_max) + "] y[" + std::to_string(params_.workspace.y_min) +
          ", " + std::to_string(params_.workspace.y_max) + "])";
  }
  if (!why.empty()) {
    // A bad goal replaces the old one with "stop": the operator meant to go somewhere else.
    report_.count("goals_rejected");
    report_.setHealth(process_status_t::HEALTH_WARN, "goal rejected: " + why);
    goal_.reset();
    cancel_pending_ = true;
    pending_message_ = "goal rejected: " + why;
    return;
  }
  nav_goal_t g = msg;
  if (!(std::isfinite(g.tolerance) && g.tolerance > 0.0)) g.tolerance = params_.goal_default_tolerance;
  // Senders repeat goals (the link may drop one): the same goal again is not a new plan.
  if (goal_ && goal_->goal_id == g.goal_id && goal_->x == g.x && goal_->y == g.y &&
      goal_->tolerance == g.tolerance && goal_->max_speed == g.max_speed &&
      (goal_->yaw == g.yaw || (std::isnan(goal_->yaw) && std::isnan(g.yaw)))) {
    report_.count("goals_repeated");
    return;
  }
  goal_ = g;
  goal_changed_ = true;
}

PlannerOutputs PlannerNode::tick(int64_t utime) {
  clock_.observe(utime);
  const int64_t now = clock_.now();
  PlannerOutputs out;
  if (now <= 0) return out;
  if (cancel_pending_) {
    cancel_pending_ = false;
    PlanInfo info;
    info.result = PlanResult::kCancelled;
    info.message = pending_message_;
    out.trajectory = stopTrajectory(now, trajectory_t::STATUS_STOP, pending_message_);
    out.plan = info;
    record(info);
    return out;
  }
  if (!goal_) return out;
  const int64_t period = int64_t(std::llround(kUsPerS / params_.rate_hz));
  const bool due = goal_changed_ || last_plan_utime_ == 0 || now - last_plan_utime_ >= period;
  bool unsafe = false;
  if (!due && current_.valid() && current_status_ == trajectory_t::STATUS_OK) {
    unsafe = check(current_msg_, now).status != trajopt::PlanStatus::kOk;
    if (unsafe) report_.count("replans_unsafe");
  }
  if (!due && !unsafe) return out;
  return plan(now, unsafe);
}

const trajopt::DistanceField2D* PlannerNode::staticField() const { return map_.ready() ? field_.get() : nullptr; }

trajopt::SafetyCheck PlannerNode::check(const trajectory_t& traj, int64_t from_utime) const {
  return trajopt::checkTrajectory(traj, from_utime, staticField(), obstacles_, params_.optimizer);
}

PlannerOutputs PlannerNode::plan(int64_t now, bool unsafe_trigger) {
  Cycle cycle;
  cycle.now = now;
  cycle.unsafe_trigger = unsafe_trigger;
  cycle.t_start = Clock::now();
  cycle.info.triggered_by_unsafe = unsafe_trigger;
  goal_changed_ = false;
  last_plan_utime_ = now;

  if (const auto missing = missingInput()) return stop(cycle, *missing, toString(*missing));
  if (goalReached()) return reachGoal(cycle);
  const StartState start = startState(now);
  updateMap(start.p, &cycle.info);
  const GuidePath guide = searchGuidePath(start.p, &cycle.info);
  if (guideUnusable(guide)) {
    return stop(cycle, PlanResult::kStopNoFeasible, std::string("front end: ") + toString(guide.status));
  }
  const std::string guide_note = noteOnGuide(guide);
  if (initialGuess(guide, start, 0).length < 0.05 && start.v.norm() < 0.05) {
    // Already at the nearest reachable point: hold here and keep the goal (the map may open),
    // unless a mover is predicted to walk into the robot there: then it evades as it does when
    // no plan passes the check.
    if (holdIsHit(cycle.now)) {
      trajopt::PlanOutput hold;
      hold.status = trajopt::PlanStatus::kDynamicCollision;
      hold.message = "holding at the nearest reachable point, a mover is predicted to reach the robot";
      rejected_.clear();
      report_.count("hold_evasions");
      return fallBack(cycle, start, hold);
    }
    return stop(cycle, PlanResult::kStopNoFeasible, guide_note.empty() ? "no progress possible" : guide_note);
  }
  const trajopt::PlanOutput po = optimise(start, guide, cycle);
  trajectory::PiecewisePolynomial accepted;
  if (!passedCheck(po, &accepted, &cycle.info)) return fallBack(cycle, start, po);
  return follow(cycle, accepted, guide_note);
}

std::optional<trajopt::PlanRequest> PlannerNode::problem(int64_t utime) {
  clock_.observe(utime);
  const int64_t now = clock_.now();
  if (now <= 0 || !goal_ || missingInput() || goalReached()) return std::nullopt;
  PlanInfo info;  // timings of this look-ahead are not reported
  const StartState start = startState(now);
  updateMap(start.p, &info);
  const GuidePath guide = searchGuidePath(start.p, &info);
  if (guideUnusable(guide)) return std::nullopt;
  const InitialGuess guess = initialGuess(guide, start, 0);
  if (guess.length < 0.05 && start.v.norm() < 0.05) return std::nullopt;
  trajopt::PlanRequest req = requestFrom(start);
  req.goal.col(0) = guess.end;
  req.inner_waypoints = guess.waypoints;
  req.durations = guess.durations;
  return req;
}

bool PlannerNode::guideUnusable(const GuidePath& guide) {
  return guide.status == GuideStatus::kNoMap || guide.status == GuideStatus::kStartOutsideMap ||
         guide.status == GuideStatus::kBadInput;
}

std::optional<PlanResult> PlannerNode::missingInput() const {
  if (!pose_ || clock_.ageSeconds(pose_->utime) > params_.pose_timeout_s) return PlanResult::kStopNoPose;
  if (!map_received_) return PlanResult::kStopNoMap;
  if (!objects_seen_ || clock_.ageSeconds(objects_utime_) > params_.objects.max_age_s)
    return PlanResult::kStopStaleObjects;
  return std::nullopt;
}

bool PlannerNode::goalReached() const {
  return (Eigen::Vector2d(pose_->x, pose_->y) - Eigen::Vector2d(goal_->x, goal_->y)).norm() <= goal_->tolerance;
}

PlannerNode::StartState PlannerNode::startState(int64_t now) {
  const Eigen::Vector2d pose_xy(pose_->x, pose_->y);
  StartState start;
  start.utime = now + int64_t(params_.latency_s * kUsPerS);
  if (current_.valid() && current_status_ == trajectory_t::STATUS_OK) {
    const Eigen::Vector3d here = current_.position(now);
    if ((here.head<2>() - pose_xy).norm() <= params_.replan_deviation && start.utime <= current_.endUtime()) {
      const auto s = current_.sample(start.utime);
      start.p = s.position.head<2>();
      start.v = s.velocity.head<2>();
      start.a = s.acceleration.head<2>();
      return start;
    }
  }
  report_.count("plan_restarts_from_pose");
  start.p = pose_xy;
  start.v = Eigen::Vector2d(pose_->vx, pose_->vy);
  start.a = finite(pose_->ax, pose_->ay) ? Eigen::Vector2d(pose_->ax, pose_->ay) : Eigen::Vector2d::Zero();
  const double vn = start.v.norm();
  if (vn > params_.optimizer.max_velocity) start.v *= params_.optimizer.max_velocity / vn;
  const double an = start.a.norm();
  if (an > params_.optimizer.max_acceleration) start.a *= params_.optimizer.max_acceleration / an;
  return start;
}

void PlannerNode::updateMap(const Eigen::Vector2d& start, PlanInfo* info) {
  const auto t0 = Clock::now();
  const bool needs_recentre =
      !map_.ready() || (start - map_.boxCenter()).cwiseAbs().maxCoeff() >= params_.map.recenter_distance;
  if (map_dirty_ || needs_recentre) {
    map_.update(start);
    map_dirty_ = false;
  }
  info->map_ms = msSince(t0);
}

GuidePath PlannerNode::searchGuidePath(const Eigen::Vector2d& start, PlanInfo* info) const {
  const auto t0 = Clock::now();
  GuidePath guide = findGuidePath(map_, start, Eigen::Vector2d(goal_->x, goal_->y), params_.front_end);
  info->front_end_ms = msSince(t0);
  info->guide = guide.status;
  return guide;
}

std::string PlannerNode::noteOnGuide(const GuidePath& guide) {
  if (guide.status == GuideStatus::kOk) return {};
  report_.count(guide.status == GuideStatus::kGoalInCollision ? "goal_in_collision" : "goal_unreachable");
  return toString(guide.status);
}

InitialGuess PlannerNode::initialGuess(const GuidePath& guide, const StartState& start, int attempt) const {
  // Later attempts are slower and shorter, which leaves the optimiser more room among moving
  // obstacles and near the limits.
  const FrontEndParams& fe = params_.front_end;
  const double slow = std::pow(params_.retry_speed_scale, attempt);
  const double length = params_.horizon_length * (attempt >= 2 ? 0.5 : 1.0);
  return makeInitialGuess(guide.points, length, start.v.norm(),
                          slow * fe.guess_speed_ratio * params_.optimizer.max_velocity,
                          fe.guess_accel_ratio * params_.optimizer.max_acceleration, fe);
}

trajopt::PlanRequest PlannerNode::requestFrom(const StartState& start) const {
  trajopt::PlanRequest req;
  req.start_utime = start.utime;
  req.start.col(0) = start.p;
  req.start.col(1) = start.v;
  req.start.col(2) = start.a;
  req.goal.setZero();
  req.field = field_.get();
  req.obstacles = obstacles_;
  return req;
}

trajopt::PlanOutput PlannerNode::optimise(const StartState& start, const GuidePath& guide, Cycle& cycle) {
  const auto t0 = Clock::now();
  trajopt::PlanRequest req = requestFrom(start);
  trajopt::PlanOutput po;
  rejected_.clear();
  int attempts = 0;
  for (int attempt = 0; attempt < params_.max_attempts; ++attempt) {
    if (attempt > 0) report_.count("plan_retries");
    const InitialGuess guess = initialGuess(guide, start, attempt);
    req.goal.col(0) = guess.end;
    req.inner_waypoints = guess.waypoints;
    req.durations = guess.durations;
    po = optimizer_.plan(req);
    keepIfLeastBadCandidate(po);
    cycle.info.iterations += po.iterations;
    ++attempts;
    if (po.status == trajopt::PlanStatus::kOk || po.status == trajopt::PlanStatus::kInvalidInput) break;
  }
  cycle.info.optimize_ms = msSince(t0);
  report_.set("attempts", attempts);
  return po;
}

bool PlannerNode::previousStillSafe(const Cycle& cycle) const {
  return current_.valid() && current_status_ == trajectory_t::STATUS_OK && !cycle.unsafe_trigger &&
         check(current_msg_, cycle.now).status == trajopt::PlanStatus::kOk;
}

void PlannerNode::reportOptimiserResult(const trajopt::PlanOutput& po, PlanInfo* info) {
  info->cost_total = po.cost.total();
  info->cost_energy = po.cost.energy;
  info->cost_time = po.cost.time;
  info->cost_static = po.cost.static_clearance;
  info->cost_dynamic = po.cost.dynamic;
  info->cost_feasibility = po.cost.velocity + po.cost.acceleration;
  report_.set("obstacles_used", po.obstacles_used);
  report_.set("min_static_clearance_m", po.min_static_clearance);
  report_.set("min_dynamic_clearance_m", po.min_dynamic_clearance);
}

bool PlannerNode::passedCheck(const trajopt::PlanOutput& po, trajectory::PiecewisePolynomial* pp, PlanInfo* info) {
  reportOptimiserResult(po, info);
  // The optimiser post-checked its result (static, predicted obstacles, limits).
  const auto t0 = Clock::now();
  const bool ok = po.status == trajopt::PlanStatus::kOk &&
                  trajectory::PiecewisePolynomial::fromMessage(po.trajectory, pp) == trajectory::TrajectoryStatus::kOk;
  info->check_ms = msSince(t0);
  if (!ok) {
    report_.count("plans_rejected");
    report_.count(std::string("rejected_") + trajopt::toString(po.status));
  }
  return ok;
}

PlannerOutputs PlannerNode::conclude(Cycle& cycle, trajectory_t trajectory) {
  PlannerOutputs out;
  out.trajectory = std::move(trajectory);
  cycle.info.total_ms = msSince(cycle.t_start);
  out.plan = cycle.info;
  record(cycle.info);
  return out;
}

PlannerOutputs PlannerNode::stop(Cycle& cycle, PlanResult result, const std::string& message) {
  cycle.info.result = result;
  cycle.info.message = message;
  return conclude(cycle, stopTrajectory(cycle.now, trajectory_t::STATUS_STOP, message));
}

PlannerOutputs PlannerNode::follow(Cycle& cycle, const trajectory::PiecewisePolynomial& pp,
                                   const std::string& message) {
  cycle.info.result = PlanResult::kOk;
  cycle.info.message = message;
  return conclude(cycle, finish(pp, cycle.now, trajectory_t::STATUS_OK, message));
}

PlannerOutputs PlannerNode::keep(Cycle& cycle, const std::string& info_message, const std::string& message) {
  cycle.info.result = PlanResult::kKeptPrevious;
  cycle.info.message = info_message;
  return conclude(cycle, resend(cycle.now, message));
}

PlannerOutputs PlannerNode::reachGoal(Cycle& cycle) {
  cycle.info.result = PlanResult::kGoalReached;
  cycle.info.message = "goal reached";
  trajectory_t t = stopTrajectory(cycle.now, trajectory_t::STATUS_GOAL_REACHED, cycle.info.message);
  goal_.reset();  // after the stopping trajectory, which carries its id
  return conclude(cycle, std::move(t));
}

}  // namespace ucon::planner
