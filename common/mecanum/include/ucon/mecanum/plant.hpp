#pragma once
/// @file plant.hpp
/// Plant model of a Mecanum base for simulation and closed-loop tests: per-wheel speed limit,
/// first-order motor lag, and integration of the forward kinematics in the world frame.
/// Deterministic (no randomness, no clock) and cheap (a few dozen flops per step).

#include "ucon/mecanum/kinematics.hpp"

namespace ucon {
class ConfigReader;

namespace mecanum {

/// Plant parameters: geometry plus motor dynamics.
struct MecanumPlantParams {
  MecanumParams geometry;             ///< kinematics; geometry.max_wheel_speed is the motor limit
  double motor_time_constant = 0.05;  ///< first-order lag tau [s], [0, 10]; 0 = ideal motors
  double max_wheel_accel = 0.0;       ///< wheel acceleration limit [rad/s^2], [0, 1e5]; 0 = none

  /// Reads section-free keys motor_time_constant, max_wheel_accel (geometry is read by the
  /// caller, usually from a shared section, with MecanumParams::read()).
  void read(ConfigReader& r);
  /// Empty if consistent, else the bad key and why.
  std::string validate() const;
};

/// Planar state of the base.
struct PlantState {
  double x = 0.0;         ///< position [m], world frame
  double y = 0.0;         ///< [m]
  double yaw = 0.0;       ///< heading [rad], wrapped to (-pi, pi]
  BodyTwist body;         ///< body-frame velocity [m/s, rad/s]
  double vx_world = 0.0;  ///< world-frame velocity [m/s]
  double vy_world = 0.0;  ///< [m/s]
  WheelSpeeds wheels;     ///< actual wheel speeds [rad/s]
};

/// The base: wheel-speed commands in, motion out. step() advances by an explicit dt.
class MecanumPlant {
 public:
  explicit MecanumPlant(const MecanumPlantParams& params);

  /// Puts the base at rest at (x, y, yaw) [m, m, rad].
  void reset(double x, double y, double yaw);
  /// Sets the full state (wheel speeds included; body and world velocities are recomputed
  /// from the wheels). Non-finite values are replaced by 0.
  void setState(const PlantState& state);

  /// Wheel speed command [rad/s], held until the next call. Each wheel is clamped to the
  /// motor limit on its own (a motor cannot exceed it); a non-finite command or enable=false
  /// commands 0 (the motors brake with the same lag). Returns false if the command had a
  /// non-finite value.
  bool setCommand(const WheelSpeeds& cmd, bool enable = true);

  /// Advances the model by dt [s]: exact first-order lag (and acceleration limit) per wheel,
  /// then the pose by the exact SE(2) motion under the mean body twist over the step (exact
  /// for straight-line motion and for constant wheel speeds). A
  /// non-finite or non-positive dt does nothing and returns false. Steps longer than 10 ms
  /// are split internally so the result hardly depends on how callers chunk time.
  bool step(double dt);

  const PlantState& state() const { return state_; }
  const WheelSpeeds& command() const { return cmd_; }
  const MecanumKinematics& kinematics() const { return kin_; }
  const MecanumPlantParams& params() const { return params_; }

 private:
  void stepOnce(double dt);
  void updateVelocities();

  MecanumPlantParams params_;
  MecanumKinematics kin_;
  PlantState state_;
  WheelSpeeds cmd_;
};

/// Wraps an angle to (-pi, pi] [rad].
double wrapAngle(double a);

}  // namespace mecanum
}  // namespace ucon
