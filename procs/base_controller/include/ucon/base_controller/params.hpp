#pragma once
/// @file params.hpp
/// Parameters of the base controller (deploy/config/base_controller.yaml maps onto these
/// one-to-one).

#include <string>

#include "ucon/mecanum/kinematics.hpp"

namespace ucon {
class ConfigReader;

namespace base_controller {

/// Trajectory tracking gains and limits (section "control").
struct ControlParams {
  double rate_hz = 100.0;             ///< control loop rate [Hz], [1, 1000]
  double lead_s = 0.03;               ///< sample the reference this far ahead of now [s], [0, 0.5]
  double kp_position = 5.0;           ///< world-frame position error gain [1/s], [0, 100]
  double kd_velocity = 0.3;           ///< velocity error gain (reference minus measured) [-], [0, 10]
  double accel_feedforward_s = 0.05;  ///< reference acceleration added as a*this [s], [0, 1]
  double max_feedback_speed = 0.6;    ///< cap on the feedback part of the velocity [m/s], [0, 10]
  double max_speed = 2.0;             ///< cap on the commanded linear speed [m/s], (0, 10]
  double max_linear_accel = 4.0;      ///< change of commanded linear velocity [m/s^2], (0, 100]
  double kp_yaw = 4.0;                ///< heading error gain [1/s], [0, 100]
  double max_yaw_rate = 2.0;          ///< cap on the commanded yaw rate [rad/s], (0, 20]
  double max_yaw_accel = 6.0;         ///< change of commanded yaw rate [rad/s^2], (0, 200]

  void read(ConfigReader& r);
};

/// How the heading is chosen when trajectory_t.yaw is NaN (section "heading").
struct HeadingParams {
  std::string mode = "hold";          ///< "hold": keep hold_yaw; "path": face along the velocity
  double hold_yaw = 0.0;              ///< heading held in "hold" mode [rad], [-pi, pi]
  double min_path_speed = 0.15;       ///< below this reference speed "path" keeps the last heading [m/s], [0, 5]

  void read(ConfigReader& r);
};

/// Safety watchdog (section "watchdog").
struct WatchdogParams {
  double pose_timeout_s = 0.2;        ///< pose older than this stops the base [s], (0, 10]
  double trajectory_timeout_s = 0.2;  ///< trajectory message older than this stops the base [s], (0, 60]
  double stop_linear_decel = 2.0;     ///< deceleration of a stop [m/s^2], (0, 100]
  double stop_angular_decel = 6.0;    ///< angular deceleration of a stop [rad/s^2], (0, 200]
  double max_reference_speed = 6.0;   ///< a plan asking for more is rejected as absurd [m/s], (0, 100]

  void read(ConfigReader& r);
};

/// Motor backend of the process (section "backend"); the node does not use it.
struct BackendParams {
  std::string type = "lcm";                   ///< "lcm" (BASE_WHEEL_CMD) or "serial"
  std::string serial_device = "/dev/ttyUSB0"; ///< tty of the motor board
  int serial_baud = 115200;                   ///< [baud], 9600 ... 921600

  void read(ConfigReader& r);
};

/// Everything the node (and its process) needs.
struct BaseControllerParams {
  /// Section "mecanum": the ucon::mecanum defaults, except the motor limit of the shipped base.
  mecanum::MecanumParams mecanum = [] {
    mecanum::MecanumParams m;
    m.max_wheel_speed = 50.0;  // [rad/s] 2.5 m/s at the rim (deploy/config/base_controller.yaml)
    return m;
  }();
  ControlParams control;              ///< section "control"
  HeadingParams heading;              ///< section "heading"
  WatchdogParams watchdog;            ///< section "watchdog"
  BackendParams backend;              ///< section "backend"
  double status_period_s = 0.05;      ///< BASE_STATUS period in message time [s], [0.001, 10]

  void read(ConfigReader& r);
  /// Empty if consistent, else the dotted key and why.
  std::string validate() const;
};

}  // namespace base_controller
}  // namespace ucon
