#pragma once
/// @file controller.hpp
/// The base controller node: trajectory + pose -> Mecanum wheel commands, with a safety
/// watchdog. No I/O and no wall clock: "now" is the utime of the messages and ticks it is
/// given, so a replay produces the same commands.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ucon/base_controller/params.hpp"
#include "ucon/base_status_t.hpp"
#include "ucon/estop_t.hpp"
#include "ucon/mecanum/kinematics.hpp"
#include "ucon/message_clock.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/wheel_cmd_t.hpp"

namespace ucon {
namespace base_controller {

/// What a handler asks the process to publish.
struct BaseControllerOutput {
  std::optional<ucon::wheel_cmd_t> wheel_cmd;  ///< BASE_WHEEL_CMD / motor backend
  std::optional<ucon::base_status_t> status;   ///< BASE_STATUS
};

/// Trajectory tracking for a Mecanum base.
///
/// Control law (world frame, each tick at time t with lead L): the reference r(t+L) is
/// sampled; the measured pose is predicted to t+L with its velocity; the velocity command is
///   v = v_r + accel_feedforward_s * a_r + sat(kp_position * (p_r - p_pred)) + kd_velocity * (v_r - v_meas),
/// capped at max_speed; the heading follows trajectory_t.yaw, or when that is NaN the
/// configured mode ("hold": hold_yaw; "path": the direction of v_r with its rate as
/// feed-forward), with kp_yaw and max_yaw_rate. The twist is rotated into the body frame,
/// scaled as a whole when a wheel would exceed max_wheel_speed (direction kept), then
/// rate-limited (max_linear_accel, max_yaw_accel) and converted by inverse kinematics.
///
/// Safety: no pose for watchdog.pose_timeout_s, a pose marked invalid, no trajectory message for
/// trajectory_timeout_s, an expired or invalid trajectory, or an E-stop -> the commanded twist
/// ramps to zero at stop_linear_decel / stop_angular_decel (direction kept) and the state says
/// why. After such a stop the base moves again only when the pose is fresh and a valid
/// trajectory has arrived after the stop began (and the E-stop is released).
///
/// Trajectories with status STOP or GOAL_REACHED are followed to their end and the end point is
/// held while the message stays fresh; when it then goes stale the base idles (no fault).
class BaseController {
 public:
  explicit BaseController(const BaseControllerParams& params);

  /// Stores the pose. A pose marked valid = false stops the base at once (the source is not
  /// localised) until a valid one arrives; non-finite fields or utime <= 0 are counted and
  /// dropped (the watchdog then sees no fresh pose).
  BaseControllerOutput onPose(const ucon::robot_pose_t& pose);

  /// Takes a new plan. A malformed one (NaN coefficients, tiny pieces, wrong sizes), one that
  /// ends before now, or one with STATUS_INVALID is rejected: the base stops and the status
  /// (returned at once) says why.
  BaseControllerOutput onTrajectory(const ucon::trajectory_t& traj);

  /// E-stop engaged: stop now (status returned at once). Released: move again once inputs
  /// are fresh.
  BaseControllerOutput onEstop(const ucon::estop_t& estop);

  /// One control step at `utime` [us] (a time earlier than the latest message time is
  /// replaced by it). Returns the wheel command and, every status_period_s or on a state
  /// change, the status.
  BaseControllerOutput tick(int64_t utime);

  /// Message time [us]: the newest utime seen.
  int64_t now() const { return clock_.now(); }
  /// A disabled, all-zero wheel command with the next sequence number, for leaving the
  /// motors braked when the process exits.
  ucon::wheel_cmd_t brakeCommand();
  int8_t state() const { return state_; }
  const std::string& reason() const { return reason_; }
  /// Counters for the process status (name, total), in a fixed order.
  std::vector<std::pair<std::string, int64_t>> counters() const;
  const BaseControllerParams& params() const { return params_; }

 private:
  /// Why a stop began; each has a counter "stops_<name>" on the process status.
  enum class StopCause {
    kPoseStale,
    kNoPose,
    kPoseInvalid,
    kTrajectoryStale,
    kTrajectoryExpired,
    kTrajectoryRejected,
    kPlannerInvalid,
    kEstop,
    kCount
  };
  static const char* counterName(StopCause c);

  struct Counters {
    int64_t poses_in = 0, poses_bad = 0, trajectories_in = 0, trajectories_rejected = 0,
            trajectories_out_of_order = 0, planner_invalid = 0, estops_in = 0, ticks = 0,
            saturated_ticks = 0, stops_while_tracking = 0, messages_older = 0;
    int64_t stops[static_cast<int>(StopCause::kCount)] = {};  ///< stops begun, by cause
  };
  struct Twist {
    double vx = 0.0, vy = 0.0, wz = 0.0;  // body frame [m/s, m/s, rad/s]
  };

  struct Decision {
    enum Kind { kTrack, kIdle, kFault } kind;
    int8_t state;        // base_status_t::STATE_* to report
    std::string reason;  // why (empty when tracking)
    StopCause cause = StopCause::kCount;  // kFault: what it counts as
  };

  /// What the inputs allow at `now` (may drop a finished final plan).
  Decision evaluate(int64_t now);
  /// Desired twist before saturation and rate limits; nullopt (and `bad`) for an absurd reference.
  std::optional<Twist> trackingTwist(int64_t now, std::string* bad);
  Twist rateLimited(const Twist& want, double dt) const;
  Twist stoppingTwist(int64_t now, double period) const;
  void enterStop(int8_t state, const std::string& reason, StopCause cause, int64_t now);
  void startRamp(int64_t now);
  ucon::base_status_t buildStatus(int64_t now);
  ucon::wheel_cmd_t buildWheelCmd(int64_t now, const mecanum::WheelSpeeds& w, bool enable,
                                  const Twist& t);

  BaseControllerParams params_;
  mecanum::MecanumKinematics kin_;
  MessageClock clock_;
  Counters n_;

  // Inputs.
  std::optional<ucon::robot_pose_t> pose_;
  bool pose_invalid_ = false;       // the newest pose message said valid = false
  trajectory::PiecewisePolynomial traj_;
  bool have_traj_ = false;          // traj_ holds an accepted plan
  int64_t traj_msg_utime_ = 0;      // utime of the latest trajectory message (any outcome)
  int64_t traj_plan_id_ = 0;
  int8_t traj_status_ = 0;
  double traj_yaw_ = 0.0;           // NaN = controller's choice
  std::string input_fault_;         // set by a rejected/invalid plan until a valid one arrives
  StopCause input_fault_cause_ = StopCause::kTrajectoryRejected;
  std::string idle_reason_ = "no trajectory";
  int64_t plans_accepted_ = 0;      // plans (or plan-less stop/goal messages) accepted so far
  bool estop_ = false;
  std::string estop_source_;

  // State.
  int8_t state_ = ucon::base_status_t::STATE_IDLE;
  std::string reason_;
  std::string fault_cause_;         // reason of the current stop
  int64_t fault_mark_ = 0;          // plans_accepted_ when it began: resume needs a newer plan
  Twist cmd_;                       // last commanded twist
  Twist stop_from_;                 // twist when the stop ramp began
  double stop_duration_ = 0.0;      // [s]
  int64_t stop_start_utime_ = 0;
  double path_yaw_ = 0.0;           // last heading chosen in "path" mode
  bool path_yaw_set_ = false;
  double saturation_ = 1.0;
  double tracking_error_ = 0.0;     // NaN when no reference
  int64_t last_tick_utime_ = 0;
  int64_t next_status_utime_ = 0;
  int64_t wheel_seq_ = 0;
  int64_t status_seq_ = 0;
};

}  // namespace base_controller
}  // namespace ucon
