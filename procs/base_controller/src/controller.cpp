#include "ucon/base_controller/controller.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ucon/mecanum/plant.hpp"  // wrapAngle

namespace ucon {
namespace base_controller {

namespace {
using ucon::base_status_t;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool isFaultState(int8_t s) {
  return s == base_status_t::STATE_STOPPING || s == base_status_t::STATE_STOPPED ||
         s == base_status_t::STATE_ESTOP;
}

bool poseFinite(const ucon::robot_pose_t& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw) && std::isfinite(p.vx) &&
         std::isfinite(p.vy) && std::isfinite(p.wz);
}

std::string trimmed(const std::string& s, std::size_t n) {
  return s.size() <= n ? s : s.substr(0, n) + "...";
}
}  // namespace

BaseController::BaseController(const BaseControllerParams& params)
    : params_(params), kin_(params.mecanum) {}

BaseControllerOutput BaseController::onPose(const ucon::robot_pose_t& pose) {
  ++n_.poses_in;
  if (pose.utime > 0 && !pose.valid && (!pose_ || pose.utime >= pose_->utime)) {
    // The source says it is not localised (odometry lost, IMU only for too long): stop now
    // rather than after the staleness timeout, and stay stopped until a valid pose and a new plan.
    ++n_.poses_bad;
    clock_.observe(pose.utime);
    pose_invalid_ = true;
    return {};
  }
  if (pose.utime <= 0 || !pose.valid || !poseFinite(pose)) {
    ++n_.poses_bad;
    return {};
  }
  if (pose_ && pose.utime < pose_->utime) {
    ++n_.messages_older;
    return {};
  }
  clock_.observe(pose.utime);
  pose_ = pose;
  pose_invalid_ = false;
  return {};
}

BaseControllerOutput BaseController::onEstop(const ucon::estop_t& estop) {
  ++n_.estops_in;
  if (estop.engaged) {
    // Honour an engage even with a bad time stamp: safety first.
    if (estop.utime > 0) clock_.observe(estop.utime);
    estop_ = true;
    estop_source_ = trimmed(estop.source, 64);
    if (state_ != base_status_t::STATE_ESTOP) {
      enterStop(base_status_t::STATE_ESTOP, "e-stop engaged by '" + estop_source_ + "'", StopCause::kEstop,
                clock_.now());
    }
  } else {
    if (estop.utime <= 0) return {};  // a release must be a well-formed message
    clock_.observe(estop.utime);
    if (estop_) fault_mark_ = plans_accepted_;  // only a plan made after the release moves it
    estop_ = false;
  }
  BaseControllerOutput out;
  out.status = buildStatus(clock_.now());
  return out;
}

BaseControllerOutput BaseController::onTrajectory(const ucon::trajectory_t& msg) {
  ++n_.trajectories_in;
  auto reject = [&](const std::string& why) {
    ++n_.trajectories_rejected;
    have_traj_ = false;
    input_fault_ = "trajectory rejected: " + why;
    input_fault_cause_ = StopCause::kTrajectoryRejected;
    if (!estop_) enterStop(base_status_t::STATE_STOPPING, input_fault_, input_fault_cause_, clock_.now());  // E-stop stays shown
    BaseControllerOutput out;
    out.status = buildStatus(clock_.now());
    return out;
  };
  if (msg.utime <= 0) return reject("utime not positive");
  if (traj_msg_utime_ > 0 && msg.utime < traj_msg_utime_) {
    ++n_.trajectories_out_of_order;
    return {};
  }
  clock_.observe(msg.utime);
  traj_msg_utime_ = msg.utime;
  const int64_t now = clock_.now();

  if (msg.status == ucon::trajectory_t::STATUS_INVALID) {
    ++n_.planner_invalid;
    have_traj_ = false;
    input_fault_ = "planner: invalid plan" + (msg.message.empty() ? "" : ": " + trimmed(msg.message, 120));
    input_fault_cause_ = StopCause::kPlannerInvalid;
    if (!estop_) enterStop(base_status_t::STATE_STOPPING, input_fault_, input_fault_cause_, now);
    BaseControllerOutput out;
    out.status = buildStatus(now);
    return out;
  }
  if (msg.status != ucon::trajectory_t::STATUS_OK && msg.status != ucon::trajectory_t::STATUS_STOP &&
      msg.status != ucon::trajectory_t::STATUS_GOAL_REACHED) {
    return reject("unknown status " + std::to_string(msg.status));
  }
  if (msg.status != ucon::trajectory_t::STATUS_OK && msg.num_pieces == 0 && msg.durations.empty() &&
      msg.coeffs.empty()) {
    // "Stop" or "goal reached" without a curve: nothing to follow, come to rest (no fault).
    have_traj_ = false;
    input_fault_.clear();
    idle_reason_ = msg.status == ucon::trajectory_t::STATUS_GOAL_REACHED ? "goal reached"
                                                                        : "planner asked to stop";
    ++plans_accepted_;
    return {};
  }
  trajectory::PiecewisePolynomial p;
  const trajectory::TrajectoryStatus st = trajectory::PiecewisePolynomial::fromMessage(msg, &p);
  if (st != trajectory::TrajectoryStatus::kOk) return reject(trajectory::toString(st));
  if (p.dim() < 2) return reject("dimension below 2");
  if (std::isinf(msg.yaw)) return reject("yaw is infinite");
  if (msg.status != ucon::trajectory_t::STATUS_GOAL_REACHED && p.endUtime() <= now) {
    return reject("entirely in the past (ended " +
                  std::to_string((now - p.endUtime()) / 1000) + " ms before now)");
  }
  traj_ = std::move(p);
  have_traj_ = true;
  traj_plan_id_ = msg.plan_id;
  traj_status_ = msg.status;
  traj_yaw_ = msg.yaw;
  input_fault_.clear();
  ++plans_accepted_;
  return {};
}

BaseController::Decision BaseController::evaluate(int64_t now) {
  const WatchdogParams& w = params_.watchdog;
  constexpr int8_t kStopping = base_status_t::STATE_STOPPING;
  if (estop_) {
    return {Decision::kFault, base_status_t::STATE_ESTOP, "e-stop engaged by '" + estop_source_ + "'", StopCause::kEstop};
  }
  if (!input_fault_.empty()) return {Decision::kFault, kStopping, input_fault_, input_fault_cause_};
  if (!have_traj_) return {Decision::kIdle, base_status_t::STATE_IDLE, idle_reason_};
  if (!pose_) return {Decision::kFault, kStopping, "watchdog: no pose received", StopCause::kNoPose};
  if (pose_invalid_) {
    return {Decision::kFault, kStopping, "pose invalid (the pose source is not localised)", StopCause::kPoseInvalid};
  }
  // Ages compared in whole microseconds so that "200 ms" means exactly 200000 us.
  if (now - pose_->utime >= std::llround(w.pose_timeout_s * 1e6)) {
    return {Decision::kFault, kStopping, "watchdog: pose stale", StopCause::kPoseStale};
  }
  const bool final_plan = traj_status_ != ucon::trajectory_t::STATUS_OK;
  if (now - traj_msg_utime_ >= std::llround(w.trajectory_timeout_s * 1e6)) {
    if (final_plan && now >= traj_.endUtime()) {
      have_traj_ = false;
      idle_reason_ = traj_status_ == ucon::trajectory_t::STATUS_GOAL_REACHED ? "goal reached"
                                                                             : "stop plan ended";
      return {Decision::kIdle, base_status_t::STATE_IDLE, idle_reason_};
    }
    return {Decision::kFault, kStopping, "watchdog: trajectory stale", StopCause::kTrajectoryStale};
  }
  if (!final_plan && now > traj_.endUtime()) {
    return {Decision::kFault, kStopping, "trajectory expired", StopCause::kTrajectoryExpired};
  }
  return {Decision::kTrack, base_status_t::STATE_TRACKING, {}};
}

void BaseController::enterStop(int8_t state, const std::string& reason, StopCause cause, int64_t now) {
  if (state_ == base_status_t::STATE_TRACKING) ++n_.stops_while_tracking;
  if (cause != StopCause::kCount) ++n_.stops[static_cast<int>(cause)];
  startRamp(now);
  state_ = state;
  reason_ = reason;
  fault_cause_ = reason;
  fault_mark_ = plans_accepted_;
}

void BaseController::startRamp(int64_t now) {
  stop_from_ = cmd_;
  const double lin = std::hypot(cmd_.vx, cmd_.vy) / params_.watchdog.stop_linear_decel;
  const double ang = std::fabs(cmd_.wz) / params_.watchdog.stop_angular_decel;
  stop_duration_ = std::max(lin, ang);
  stop_start_utime_ = now;
}

BaseController::Twist BaseController::stoppingTwist(int64_t now, double period) const {
  // The command holds for the next period, so aim at the ramp's value at its end: the first
  // reduction is applied on the tick that starts the stop and zero is reached within
  // stop_duration_ of it, never faster than the configured deceleration.
  if (!(stop_duration_ > 0.0)) return Twist{};
  const double elapsed = static_cast<double>(now - stop_start_utime_) * 1e-6 + period;
  const double s = std::max(0.0, 1.0 - elapsed / stop_duration_);
  if (s <= 0.0) return Twist{};
  return Twist{stop_from_.vx * s, stop_from_.vy * s, stop_from_.wz * s};
}

std::optional<BaseController::Twist> BaseController::trackingTwist(int64_t now, std::string* bad) {
  const ControlParams& c = params_.control;
  const ucon::robot_pose_t& pose = *pose_;
  const int64_t lead_us = static_cast<int64_t>(std::llround(c.lead_s * 1e6));
  const int64_t t_ref = now + lead_us;
  const trajectory::TrajectorySample ref = traj_.sample(t_ref);
  const trajectory::TrajectorySample ref_now = traj_.sample(now);
  // A well-formed plan can still be absurd (huge coefficients from a diverged optimiser).
  const double ref_speed = std::max(ref.velocity.norm(), ref_now.velocity.norm());
  if (!ref.position.allFinite() || !ref.velocity.allFinite() || !ref.acceleration.allFinite() ||
      !ref_now.position.allFinite() || !ref_now.velocity.allFinite() || !(ref_speed <= params_.watchdog.max_reference_speed)) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), "reference speed %.3g m/s above watchdog.max_reference_speed", ref_speed);
    *bad = std::isfinite(ref_speed) ? buf : "reference not finite";
    return std::nullopt;
  }

  // Predict the measured pose to the reference time (covers pose latency and actuation lag).
  const double h = std::clamp(static_cast<double>(t_ref - pose.utime) * 1e-6, 0.0, 0.5);
  const double px = pose.x + pose.vx * h;
  const double py = pose.y + pose.vy * h;
  const double yaw_pred = mecanum::wrapAngle(pose.yaw + pose.wz * h);
  const double h_now = std::clamp(static_cast<double>(now - pose.utime) * 1e-6, 0.0, 0.5);
  tracking_error_ = std::hypot(ref_now.position.x() - (pose.x + pose.vx * h_now),
                               ref_now.position.y() - (pose.y + pose.vy * h_now));

  // World-frame velocity: feed-forward + saturated position feedback + velocity feedback.
  double fbx = c.kp_position * (ref.position.x() - px);
  double fby = c.kp_position * (ref.position.y() - py);
  const double fb = std::hypot(fbx, fby);
  if (fb > c.max_feedback_speed) {
    fbx *= c.max_feedback_speed / fb;
    fby *= c.max_feedback_speed / fb;
  }
  double vx = ref.velocity.x() + c.accel_feedforward_s * ref.acceleration.x() + fbx +
              c.kd_velocity * (ref_now.velocity.x() - pose.vx);
  double vy = ref.velocity.y() + c.accel_feedforward_s * ref.acceleration.y() + fby +
              c.kd_velocity * (ref_now.velocity.y() - pose.vy);
  const double speed = std::hypot(vx, vy);
  if (speed > c.max_speed) {
    vx *= c.max_speed / speed;
    vy *= c.max_speed / speed;
  }

  // Heading: the plan's yaw, else the configured mode.
  double yaw_ref = params_.heading.hold_yaw;
  double wz_ff = 0.0;
  if (std::isfinite(traj_yaw_)) {
    yaw_ref = traj_yaw_;
  } else if (params_.heading.mode == "path") {
    const double rvx = ref.velocity.x(), rvy = ref.velocity.y();
    const double rs2 = rvx * rvx + rvy * rvy;
    if (std::sqrt(rs2) >= params_.heading.min_path_speed) {
      path_yaw_ = std::atan2(rvy, rvx);
      // d/dt atan2(vy, vx) = (vx ay - vy ax) / |v|^2
      wz_ff = (rvx * ref.acceleration.y() - rvy * ref.acceleration.x()) / rs2;
      path_yaw_set_ = true;
    } else if (!path_yaw_set_) {
      path_yaw_ = pose.yaw;
      path_yaw_set_ = true;
    }
    yaw_ref = path_yaw_;
  }
  double wz = wz_ff + c.kp_yaw * mecanum::wrapAngle(yaw_ref - yaw_pred);
  wz = std::clamp(wz, -c.max_yaw_rate, c.max_yaw_rate);

  // Body frame at the predicted heading.
  const double cy = std::cos(yaw_pred), sy = std::sin(yaw_pred);
  return Twist{cy * vx + sy * vy, -sy * vx + cy * vy, wz};
}

BaseController::Twist BaseController::rateLimited(const Twist& want, double dt) const {
  // Acceleration limits relative to the last command (direction of the change kept). Both
  // the last command and `want` are within the wheel limits, and that set is convex, so every
  // point between them is too.
  const ControlParams& c = params_.control;
  Twist out = want;
  const double dvx = want.vx - cmd_.vx, dvy = want.vy - cmd_.vy;
  const double dv = std::hypot(dvx, dvy), dv_max = c.max_linear_accel * dt;
  if (dv > dv_max) {
    out.vx = cmd_.vx + dvx * (dv_max / dv);
    out.vy = cmd_.vy + dvy * (dv_max / dv);
  }
  const double dw_max = c.max_yaw_accel * dt;
  out.wz = cmd_.wz + std::clamp(want.wz - cmd_.wz, -dw_max, dw_max);
  return out;
}

BaseControllerOutput BaseController::tick(int64_t utime) {
  const MessageClock::Observation obs = clock_.observe(utime);
  if (obs == MessageClock::Observation::kOlder) ++n_.messages_older;
  BaseControllerOutput out;
  const int64_t now = clock_.now();
  if (now <= 0) return out;  // nothing known yet
  ++n_.ticks;
  const double period = 1.0 / params_.control.rate_hz;
  double dt = last_tick_utime_ > 0 ? static_cast<double>(now - last_tick_utime_) * 1e-6 : period;
  dt = std::clamp(dt, 0.0, 5.0 * period);
  last_tick_utime_ = now;

  const int8_t prev_state = state_;
  const std::string prev_reason = reason_;
  const Decision d = evaluate(now);
  if (d.kind == Decision::kFault) {
    if (!isFaultState(state_) || fault_cause_ != d.reason ||
        (d.state == base_status_t::STATE_ESTOP) != (state_ == base_status_t::STATE_ESTOP)) {
      enterStop(d.state, d.reason, d.cause, now);
    }
  } else if (d.kind == Decision::kIdle) {
    if (state_ != base_status_t::STATE_IDLE) {
      startRamp(now);
      state_ = base_status_t::STATE_IDLE;
    }
    reason_ = d.reason;
  } else {  // kTrack
    if (isFaultState(state_) && plans_accepted_ <= fault_mark_) {
      // The cause is gone, but only a plan made after the stop may move the base again.
      if (state_ == base_status_t::STATE_ESTOP) state_ = base_status_t::STATE_STOPPING;
      reason_ = fault_cause_ + " (cleared; waiting for a new trajectory)";
    } else {
      state_ = base_status_t::STATE_TRACKING;
      const bool holding = traj_status_ != ucon::trajectory_t::STATUS_OK && now >= traj_.endUtime();
      reason_ = holding ? (traj_status_ == ucon::trajectory_t::STATUS_GOAL_REACHED
                               ? "holding: goal reached"
                               : "holding: end of stop plan")
                        : std::string();
    }
  }

  Twist twist;
  mecanum::WheelSpeeds wheels;
  if (state_ == base_status_t::STATE_TRACKING) {
    // Saturate the desired twist first (keeps its direction; the factor is what the status
    // reports), then limit the change from the last command.
    std::string bad;
    const std::optional<Twist> want = trackingTwist(now, &bad);
    const mecanum::Saturated sat =
        want ? mecanum::saturate(kin_.inverse({want->vx, want->vy, want->wz}), params_.mecanum.max_wheel_speed)
             : mecanum::Saturated{mecanum::WheelSpeeds{}, 0.0};
    if (!want || sat.scale <= 0.0) {
      // An absurd reference, or a non-finite command (absurd pose): never send it; treat the
      // plan as rejected and stop.
      ++n_.trajectories_rejected;
      have_traj_ = false;
      input_fault_ = "trajectory rejected: " + (bad.empty() ? std::string("command not finite") : bad);
      input_fault_cause_ = StopCause::kTrajectoryRejected;
      enterStop(base_status_t::STATE_STOPPING, input_fault_, input_fault_cause_, now);
      saturation_ = 1.0;
      tracking_error_ = kNaN;
      twist = stoppingTwist(now, period);
    } else {
      saturation_ = sat.scale;
      if (sat.scale < 1.0) ++n_.saturated_ticks;
      twist = rateLimited(Twist{want->vx * sat.scale, want->vy * sat.scale, want->wz * sat.scale}, dt);
    }
    // Within the limits by construction; saturate() again only guards rounding.
    wheels = mecanum::saturate(kin_.inverse({twist.vx, twist.vy, twist.wz}), params_.mecanum.max_wheel_speed).wheels;
  } else {
    twist = stoppingTwist(now, period);
    wheels = kin_.inverse({twist.vx, twist.vy, twist.wz});
    saturation_ = 1.0;
    tracking_error_ = kNaN;
    if (state_ == base_status_t::STATE_STOPPING && twist.vx == 0.0 && twist.vy == 0.0 &&
        twist.wz == 0.0) {
      state_ = base_status_t::STATE_STOPPED;
    }
  }
  cmd_ = twist;
  const bool at_rest = twist.vx == 0.0 && twist.vy == 0.0 && twist.wz == 0.0;
  const bool enable = state_ == base_status_t::STATE_TRACKING || !at_rest;
  out.wheel_cmd = buildWheelCmd(now, wheels, enable, twist);

  if (now >= next_status_utime_ || state_ != prev_state || reason_ != prev_reason) {
    out.status = buildStatus(now);
    next_status_utime_ = now + static_cast<int64_t>(std::llround(params_.status_period_s * 1e6));
  }
  return out;
}

ucon::wheel_cmd_t BaseController::brakeCommand() {
  return buildWheelCmd(clock_.now(), mecanum::WheelSpeeds{}, false, Twist{});
}

ucon::wheel_cmd_t BaseController::buildWheelCmd(int64_t now, const mecanum::WheelSpeeds& w,
                                                bool enable, const Twist& t) {
  ucon::wheel_cmd_t m{};
  m.utime = now;
  m.seq = wheel_seq_++;
  m.enable = enable;
  m.w_fl = w.fl;
  m.w_fr = w.fr;
  m.w_rl = w.rl;
  m.w_rr = w.rr;
  m.vx = t.vx;
  m.vy = t.vy;
  m.wz = t.wz;
  return m;
}

ucon::base_status_t BaseController::buildStatus(int64_t now) {
  ucon::base_status_t s{};
  s.utime = now;
  s.seq = status_seq_++;
  s.state = state_;
  s.reason = reason_;
  s.plan_id = have_traj_ ? traj_plan_id_ : 0;
  s.tracking_error = state_ == base_status_t::STATE_TRACKING ? tracking_error_ : kNaN;
  s.cmd_vx = cmd_.vx;
  s.cmd_vy = cmd_.vy;
  s.cmd_wz = cmd_.wz;
  s.saturation = saturation_;
  s.pose_age_ms = pose_ ? static_cast<double>(now - pose_->utime) / 1000.0 : -1.0;
  s.trajectory_age_ms = traj_msg_utime_ > 0 ? static_cast<double>(now - traj_msg_utime_) / 1000.0 : -1.0;
  s.rejected_trajectories = n_.trajectories_rejected;
  return s;
}

const char* BaseController::counterName(StopCause c) {
  switch (c) {
    case StopCause::kPoseStale: return "stops_pose_stale";
    case StopCause::kNoPose: return "stops_no_pose";
    case StopCause::kPoseInvalid: return "stops_pose_invalid";
    case StopCause::kTrajectoryStale: return "stops_trajectory_stale";
    case StopCause::kTrajectoryExpired: return "stops_trajectory_expired";
    case StopCause::kTrajectoryRejected: return "stops_trajectory_rejected";
    case StopCause::kPlannerInvalid: return "stops_planner_invalid";
    case StopCause::kEstop: return "stops_estop";
    case StopCause::kCount: break;
  }
  return "stops_other";
}

std::vector<std::pair<std::string, int64_t>> BaseController::counters() const {
  std::vector<std::pair<std::string, int64_t>> out = {{"poses_in", n_.poses_in},
          {"poses_bad", n_.poses_bad},
          {"trajectories_in", n_.trajectories_in},
          {"trajectories_rejected", n_.trajectories_rejected},
          {"trajectories_out_of_order", n_.trajectories_out_of_order},
          {"planner_invalid", n_.planner_invalid},
          {"estops_in", n_.estops_in},
          {"ticks", n_.ticks},
          {"saturated_ticks", n_.saturated_ticks},
          {"stops_while_tracking", n_.stops_while_tracking},
          {"messages_older", n_.messages_older}};
  // The watchdog's and the input checks' stops by cause (BASE_STATUS has the current one only).
  for (int c = 0; c < static_cast<int>(StopCause::kCount); ++c) {
    out.emplace_back(counterName(static_cast<StopCause>(c)), n_.stops[c]);
  }
  return out;
}

}  // namespace base_controller
}  // namespace ucon
