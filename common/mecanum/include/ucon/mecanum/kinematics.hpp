#pragma once
/// @file kinematics.hpp
/// Mecanum base kinematics (rollers at 45 degrees, X configuration seen from above;
/// docs/reference.md §7), wheel-speed saturation that keeps the direction of motion, and the
/// mapping between the canonical wheel order (FL, FR, RL, RR; positive rolls the robot forward)
/// and the motor channels of a motor board (order and sign from the parameters).

#include <array>
#include <string>

namespace ucon {
class ConfigReader;

namespace mecanum {

/// Body-frame twist: vx forward, vy left [m/s], wz counter-clockwise [rad/s].
struct BodyTwist {
  double vx = 0.0;  ///< [m/s]
  double vy = 0.0;  ///< [m/s]
  double wz = 0.0;  ///< [rad/s]
};

/// Wheel angular speeds in the canonical order; positive rolls the robot forward [rad/s].
struct WheelSpeeds {
  double fl = 0.0;  ///< front-left [rad/s]
  double fr = 0.0;  ///< front-right [rad/s]
  double rl = 0.0;  ///< rear-left [rad/s]
  double rr = 0.0;  ///< rear-right [rad/s]

  /// {fl, fr, rl, rr}.
  std::array<double, 4> toArray() const { return {fl, fr, rl, rr}; }
  /// From {fl, fr, rl, rr}.
  static WheelSpeeds fromArray(const std::array<double, 4>& a) { return {a[0], a[1], a[2], a[3]}; }
  /// Largest |speed| of the four [rad/s]; NaN if any is NaN.
  double maxAbs() const;
  /// True if all four are finite.
  bool allFinite() const;
};

/// Geometry of the base and the motor-channel mapping.
struct MecanumParams {
  double wheel_radius = 0.05;     ///< r [m], (0, 1]
  double half_wheelbase = 0.20;   ///< lx, wheel axle to centre along x [m], (0, 5]
  double half_track = 0.20;       ///< ly, wheel to centre along y [m], (0, 5]
  double max_wheel_speed = 30.0;  ///< saturation limit per wheel [rad/s], (0, 1000]
  /// motor_order[i] = canonical wheel (0 FL, 1 FR, 2 RL, 3 RR) driven by motor channel i.
  std::array<int, 4> motor_order{{0, 1, 2, 3}};
  /// motor_sign[i] = +1 or -1: multiplies the canonical speed for motor channel i (mirror-mounted
  /// motors turn the other way for the same robot motion).
  std::array<int, 4> motor_sign{{1, 1, 1, 1}};

  /// Reads keys wheel_radius, half_wheelbase, half_track, max_wheel_speed, motor_order (4
  /// integers, a permutation of 0..3), motor_sign (4 values, each +1 or -1).
  void read(ConfigReader& r);
  /// Empty if consistent, else the name of the bad key and why.
  std::string validate() const;
};

/// Inverse and forward kinematics of one base.
class MecanumKinematics {
 public:
  explicit MecanumKinematics(const MecanumParams& params) : p_(params) {}

  /// Wheel speeds [rad/s] that produce the body twist (docs/reference.md §7):
  /// w_FL = (vx - vy - (lx+ly) wz)/r, w_FR = (vx + vy + (lx+ly) wz)/r,
  /// w_RL = (vx + vy - (lx+ly) wz)/r, w_RR = (vx - vy + (lx+ly) wz)/r.
  WheelSpeeds inverse(const BodyTwist& twist) const;

  /// Body twist from wheel speeds: the least-squares inverse of inverse() (exact when the
  /// wheel speeds are consistent, i.e. come from inverse()).
  BodyTwist forward(const WheelSpeeds& wheels) const;

  /// Wheel speeds in motor-channel order with the motor signs applied.
  std::array<double, 4> toMotor(const WheelSpeeds& wheels) const;
  /// Inverse of toMotor().
  WheelSpeeds fromMotor(const std::array<double, 4>& motor) const;

  const MecanumParams& params() const { return p_; }

 private:
  MecanumParams p_;
};

/// Result of saturate().
struct Saturated {
  WheelSpeeds wheels;  ///< scaled wheel speeds [rad/s]
  /// Factor applied to all four wheels, (0, 1]; 1 = within limits. 0 when the input had a
  /// non-finite speed (then all wheels are 0).
  double scale = 1.0;
};

/// Scales all four wheel speeds by the same factor so that none exceeds `max_speed` [rad/s]:
/// the ratio between wheels, hence the direction of the body twist, is kept. Non-finite input
/// gives zero wheels with scale 0.
Saturated saturate(const WheelSpeeds& wheels, double max_speed);

}  // namespace mecanum
}  // namespace ucon
