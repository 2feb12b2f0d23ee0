#include "ucon/planner/planner_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ucon/trajectory/quintic_hermite.hpp"

namespace ucon::planner {

const char* toString(PlanResult r) {
  switch (r) {
    case PlanResult::kOk: return "ok";
    case PlanResult::kGoalReached: return "goal reached";
    case PlanResult::kStopNoFeasible: return "no feasible trajectory: stopping";
    case PlanResult::kStopNoPose: return "no valid pose: stopping";
    case PlanResult::kStopNoMap: return "no static map yet: stopping";
    case PlanResult::kStopStaleObjects: return "moving obstacles stale or missing: stopping";
    case PlanResult::kCancelled: return "goal cancelled: stopping";
    case PlanResult::kKeptPrevious: return "new plan failed its check: keeping the previous one";
  }
  return "unknown";
}

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
      optimizer_(params.optimizer, params.kalman) {}

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

trajopt::SafetyCheck PlannerNode::check(const trajectory_t& traj, int64_t from_utime) const {
  return trajopt::checkTrajectory(traj, from_utime, map_.ready() ? field_.get() : nullptr, obstacles_,
                                  params_.optimizer);
}

PlannerOutputs PlannerNode::plan(int64_t now, bool unsafe_trigger) {
  const auto t_start = Clock::now();
  PlannerOutputs out;
  PlanInfo info;
  info.triggered_by_unsafe = unsafe_trigger;
  goal_changed_ = false;
  last_plan_utime_ = now;
  auto stop = [&](PlanResult r, const std::string& msg) {
    info.result = r;
    info.message = msg;
    out.trajectory = stopTrajectory(now, trajectory_t::STATUS_STOP, msg);
    info.total_ms = msSince(t_start);
    out.plan = info;
    record(info);
    return out;
  };
  auto follow = [&](const trajectory::PiecewisePolynomial& pp, const std::string& msg) {
    info.result = PlanResult::kOk;
    info.message = msg;
    out.trajectory = finish(pp, now, trajectory_t::STATUS_OK, msg);
    info.total_ms = msSince(t_start);
    out.plan = info;
    record(info);
    return out;
  };
  // The current plan goes out again, stamped now: the base controller stops on a trajectory
  // older than its watchdog (0.2 s), and a planner that keeps its plan for two cycles in a row
  // must not look like a silent one.
  auto keep = [&](const std::string& info_msg, const std::string& msg) {
    info.result = PlanResult::kKeptPrevious;
    info.message = info_msg;
    out.trajectory = resend(now, msg);
    info.total_ms = msSince(t_start);
    out.plan = info;
    record(info);
    return out;
  };

  // Inputs.
  if (!pose_ || clock_.ageSeconds(pose_->utime) > params_.pose_timeout_s) {
    return stop(PlanResult::kStopNoPose, toString(PlanResult::kStopNoPose));
  }
  if (!map_received_) return stop(PlanResult::kStopNoMap, toString(PlanResult::kStopNoMap));
  if (!objects_seen_ || clock_.ageSeconds(objects_utime_) > params_.objects.max_age_s) {
    return stop(PlanResult::kStopStaleObjects, toString(PlanResult::kStopStaleObjects));
  }
  const Eigen::Vector2d pose_xy(pose_->x, pose_->y);
  const Eigen::Vector2d goal_xy(goal_->x, goal_->y);
  if ((pose_xy - goal_xy).norm() <= goal_->tolerance) {
    info.result = PlanResult::kGoalReached;
    info.message = "goal reached";
    out.trajectory = stopTrajectory(now, trajectory_t::STATUS_GOAL_REACHED, info.message);
    goal_.reset();
    info.total_ms = msSince(t_start);
    out.plan = info;
    record(info);
    return out;
  }

  // Start state: the current plan at now + latency when the robot follows it, else the pose.
  StartState start;
  start.utime = now + int64_t(params_.latency_s * kUsPerS);
  bool from_plan = false;
  if (current_.valid() && current_status_ == trajectory_t::STATUS_OK) {
    const Eigen::Vector3d here = current_.position(now);
    if ((here.head<2>() - pose_xy).norm() <= params_.replan_deviation && start.utime <= current_.endUtime()) {
      const auto s = current_.sample(start.utime);
      start.p = s.position.head<2>();
      start.v = s.velocity.head<2>();
      start.a = s.acceleration.head<2>();
      from_plan = true;
    }
  }
  if (!from_plan) {
    report_.count("plan_restarts_from_pose");
    start.p = pose_xy;
    start.v = Eigen::Vector2d(pose_->vx, pose_->vy);
    start.a = finite(pose_->ax, pose_->ay) ? Eigen::Vector2d(pose_->ax, pose_->ay) : Eigen::Vector2d::Zero();
    const double vn = start.v.norm();
    if (vn > params_.optimizer.max_velocity) start.v *= params_.optimizer.max_velocity / vn;
    const double an = start.a.norm();
    if (an > params_.optimizer.max_acceleration) start.a *= params_.optimizer.max_acceleration / an;
  }

  // Map.
  auto t0 = Clock::now();
  const bool needs_recentre =
      !map_.ready() || (start.p - map_.boxCenter()).cwiseAbs().maxCoeff() >= params_.map.recenter_distance;
  if (map_dirty_ || needs_recentre) {
    map_.update(start.p);
    map_dirty_ = false;
  }
  info.map_ms = msSince(t0);

  // Front end.
  t0 = Clock::now();
  const GuidePath guide = findGuidePath(map_, start.p, goal_xy, params_.front_end);
  info.front_end_ms = msSince(t0);
  info.guide = guide.status;
  if (guide.status == GuideStatus::kNoMap || guide.status == GuideStatus::kStartOutsideMap ||
      guide.status == GuideStatus::kBadInput) {
    return stop(PlanResult::kStopNoFeasible, std::string("front end: ") + toString(guide.status));
  }
  std::string guide_note;
  if (guide.status != GuideStatus::kOk) {
    report_.count(guide.status == GuideStatus::kGoalInCollision ? "goal_in_collision" : "goal_unreachable");
    guide_note = toString(guide.status);
  }
  const FrontEndParams& fe = params_.front_end;
  auto guessFor = [&](int attempt) {
    // Attempt 0: the nominal guess; later attempts are slower and shorter, which leaves the
    // optimiser more room among moving obstacles and near the limits.
    const double slow = std::pow(params_.retry_speed_scale, attempt);
    const double length = params_.horizon_length * (attempt >= 2 ? 0.5 : 1.0);
    return makeInitialGuess(guide.points, length, start.v.norm(),
                            slow * fe.guess_speed_ratio * params_.optimizer.max_velocity,
                            fe.guess_accel_ratio * params_.optimizer.max_acceleration, fe);
  };
  InitialGuess guess = guessFor(0);
  if (guess.length < 0.05 && start.v.norm() < 0.05) {
    // Already at the nearest reachable point: hold here and keep the goal (the map may open).
    return stop(PlanResult::kStopNoFeasible, guide_note.empty() ? "no progress possible" : guide_note);
  }

  // Back end: sector-MINCO from the start state to rest at the end of the guide.
  t0 = Clock::now();
  trajopt::PlanRequest req;
  req.start_utime = start.utime;
  req.start.col(0) = start.p;
  req.start.col(1) = start.v;
  req.start.col(2) = start.a;
  req.goal.setZero();
  req.field = field_.get();
  req.obstacles = obstacles_;
  trajopt::PlanOutput po;
  fallback_.reset();
  int attempts = 0;
  for (int attempt = 0; attempt < params_.max_attempts; ++attempt) {
    if (attempt > 0) {
      report_.count("plan_retries");
      guess = guessFor(attempt);
    }
    req.goal.col(0) = guess.end;
    req.inner_waypoints = guess.waypoints;
    req.durations = guess.durations;
    po = optimizer_.plan(req);
    considerFallback(po);
    info.iterations += po.iterations;
    ++attempts;
    if (po.status == trajopt::PlanStatus::kOk || po.status == trajopt::PlanStatus::kInvalidInput) break;
  }
  std::string evasive_note;
  const auto previousStillSafe = [&] {
    return current_.valid() && current_status_ == trajectory_t::STATUS_OK && !unsafe_trigger &&
           check(current_msg_, now).status == trajopt::PlanStatus::kOk;
  };
  if (po.status != trajopt::PlanStatus::kOk && po.status != trajopt::PlanStatus::kInvalidInput &&
      params_.escape_candidates > 0 && !previousStillSafe()) {
    // Nothing toward the goal passed the check. Before braking (which leaves the robot in the
    // way of whatever is coming), try short detours in the directions that stay farthest from
    // the predicted obstacles; each still has to pass the same post-check.
    const trajopt::PlanOutput escape = planEscape(start, req, &info.iterations);
    if (escape.status == trajopt::PlanStatus::kOk) {
      po = escape;
      evasive_note = "evasive detour: no checked plan toward the goal";
      report_.count("evasive_plans");
    }
  }
  info.optimize_ms = msSince(t0);
  report_.set("attempts", attempts);
  info.cost_total = po.cost.total();
  info.cost_energy = po.cost.energy;
  info.cost_time = po.cost.time;
  info.cost_static = po.cost.static_clearance;
  info.cost_dynamic = po.cost.dynamic;
  info.cost_feasibility = po.cost.velocity + po.cost.acceleration;
  report_.set("obstacles_used", po.obstacles_used);
  report_.set("min_static_clearance_m", po.min_static_clearance);
  report_.set("min_dynamic_clearance_m", po.min_dynamic_clearance);

  // The optimiser post-checked its result (static, predicted obstacles, limits).
  t0 = Clock::now();
  trajectory::PiecewisePolynomial candidate;
  const bool ok = po.status == trajopt::PlanStatus::kOk &&
                  trajectory::PiecewisePolynomial::fromMessage(po.trajectory, &candidate) ==
                      trajectory::TrajectoryStatus::kOk;
  info.check_ms = msSince(t0);
  if (!ok) {
    report_.count("plans_rejected");
    report_.count(std::string("rejected_") + trajopt::toString(po.status));
    const std::string why = std::string(trajopt::toString(po.status)) +
                            (po.message.empty() ? "" : ": " + po.message);
    if (previousStillSafe()) return keep("rejected: " + why, "kept previous plan; new one rejected: " + why);
    if (params_.evasion.enabled) {
      const Evasion e = evade(now);
      if (e.kind == Evasion::kBrake) return stop(PlanResult::kStopNoFeasible, "no feasible trajectory: " + why);
      if (e.kind == Evasion::kKeep) return keep(e.message, e.message);
      return follow(e.pp, e.message);
    }
    // Braking leaves the robot where it is: when a rejected plan is predicted to reach the
    // movers clearly later than braking does, following it is the safer choice (the next
    // cycle replans from there).
    trajectory::PiecewisePolynomial stop_pp;
    if (params_.least_bad_gain_s >= 0.0 && fallback_ && stopPolynomial(now, &stop_pp)) {
      const double t_stop = firstContact(stop_pp, start.utime);
      if (fallback_->contact_s >= t_stop + params_.least_bad_gain_s) {
        report_.count("least_bad_plans");
        char buf[160];
        std::snprintf(buf, sizeof(buf), "least bad: movers predicted within reach after %.2f s, braking %.2f s",
                      fallback_->contact_s, t_stop);
        return follow(fallback_->pp, buf);
      }
    }
    return stop(PlanResult::kStopNoFeasible, "no feasible trajectory: " + why);
  }
  return follow(candidate, evasive_note.empty() ? guide_note : evasive_note);
}

PlannerNode::Evasion PlannerNode::evade(int64_t now) {
  // Braking, the least-bad rejected plan and the fan of manoeuvres, by one score (evasion.hpp).
  const int64_t t0 = now + int64_t(params_.latency_s * kUsPerS);
  const trajopt::DistanceField2D* field = map_.ready() ? field_.get() : nullptr;
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

trajectory_t PlannerNode::finish(const trajectory::PiecewisePolynomial& pp, int64_t now, int8_t status,
                                 const std::string& message) {
  trajectory_t msg{};
  pp.toMessage(&msg);
  msg.utime = now;
  msg.seq = ++seq_;
  msg.plan_id = ++plan_id_;
  msg.goal_id = goal_ ? goal_->goal_id : 0;
  msg.status = status;
  msg.message = message;
  msg.yaw = (goal_ && std::isfinite(goal_->yaw)) ? goal_->yaw : std::numeric_limits<double>::quiet_NaN();
  current_ = pp;
  current_msg_ = msg;
  current_status_ = status;
  return msg;
}

trajectory_t PlannerNode::resend(int64_t now, const std::string& message) {
  current_msg_.utime = now;
  current_msg_.seq = ++seq_;
  current_msg_.message = message;
  return current_msg_;  // same plan_id: the controller keeps following the same curve
}

void PlannerNode::considerFallback(const trajopt::PlanOutput& po) {
  if (params_.least_bad_gain_s < 0.0 || po.status != trajopt::PlanStatus::kDynamicCollision) return;
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

trajectory_t PlannerNode::stopTrajectory(int64_t now, int8_t status, const std::string& message) {
  trajectory::PiecewisePolynomial pp;
  if (stopPolynomial(now, &pp)) return finish(pp, now, status, message);
  trajectory_t msg{};
  msg.utime = now;
  msg.seq = ++seq_;
  msg.plan_id = ++plan_id_;
  msg.goal_id = goal_ ? goal_->goal_id : 0;
  msg.status = trajectory_t::STATUS_INVALID;
  msg.message = message.empty() ? "no state to stop from" : message;
  msg.dim = 2;
  msg.order1 = 6;
  msg.yaw = std::numeric_limits<double>::quiet_NaN();
  current_ = trajectory::PiecewisePolynomial();
  current_msg_ = msg;
  current_status_ = msg.status;
  return msg;
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

void PlannerNode::record(const PlanInfo& info) {
  report_.count("plans");
  report_.count(std::string("result_") + [&] {
    switch (info.result) {
      case PlanResult::kOk: return "ok";
      case PlanResult::kGoalReached: return "goal_reached";
      case PlanResult::kStopNoFeasible: return "stop_no_feasible";
      case PlanResult::kStopNoPose: return "stop_no_pose";
      case PlanResult::kStopNoMap: return "stop_no_map";
      case PlanResult::kStopStaleObjects: return "stop_stale_objects";
      case PlanResult::kCancelled: return "cancelled";
      case PlanResult::kKeptPrevious: return "kept_previous";
    }
    return "unknown";
  }());
  report_.time("map", info.map_ms);
  report_.time("front_end", info.front_end_ms);
  report_.time("optimize", info.optimize_ms);
  report_.time("check", info.check_ms);
  report_.time("plan_total", info.total_ms);
  report_.set("result", double(int(info.result)));
  report_.set("iterations", info.iterations);
  report_.set("cost_total", info.cost_total);
  report_.set("cost_energy", info.cost_energy);
  report_.set("cost_time", info.cost_time);
  report_.set("cost_static", info.cost_static);
  report_.set("cost_dynamic", info.cost_dynamic);
  report_.set("cost_feasibility", info.cost_feasibility);
  switch (info.result) {
    case PlanResult::kOk:
    case PlanResult::kGoalReached:
    case PlanResult::kKeptPrevious:
      if (info.guide == GuideStatus::kOk) {
        report_.setHealth(process_status_t::HEALTH_OK, "");
      } else {
        report_.setHealth(process_status_t::HEALTH_WARN, toString(info.guide));
      }
      break;
    case PlanResult::kCancelled:
      report_.setHealth(info.message == "goal cancelled" ? process_status_t::HEALTH_OK
                                                         : process_status_t::HEALTH_WARN,
                        info.message == "goal cancelled" ? "" : info.message);
      break;
    default:
      // Holding at the nearest reachable point of a blocked goal is a warning, not a fault.
      report_.setHealth(info.guide == GuideStatus::kGoalInCollision || info.guide == GuideStatus::kGoalUnreachable
                            ? process_status_t::HEALTH_WARN
                            : process_status_t::HEALTH_ERROR,
                        info.message);
  }
}

}  // namespace ucon::planner
