#pragma once
/// @file so3.hpp
/// The rotation group SO(3): exponential and logarithm maps and the right Jacobians the
/// error-state filter needs. Perturbations are on the right, in the body frame:
/// R = R_hat * Exp(dtheta). Angles in radians.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace ucon {
namespace lio {

/// Skew-symmetric matrix [v]x, so that hat(a) * b = a x b.
inline Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// Exp: rotation vector [rad] -> rotation matrix (Rodrigues). Below 0.03 rad (the rotation of
/// an IMU step or of a point's time offset) the coefficients come from their Taylor series to
/// t^4 (error below 1e-12), which spares the trigonometry done per point.
inline Eigen::Matrix3d expSO3(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d W = hat(w);
  if (t2 < 1e-3) {
    const double a = 1.0 - t2 / 6.0 + t2 * t2 / 120.0;   // sin(t) / t
    const double b = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;  // (1 - cos(t)) / t^2
    return Eigen::Matrix3d::Identity() + a * W + b * W * W;
  }
  const double t = std::sqrt(t2);
  return Eigen::Matrix3d::Identity() + (std::sin(t) / t) * W + ((1.0 - std::cos(t)) / t2) * W * W;
}

/// Exp(w) p without forming the matrix: p + a (w x p) + b w x (w x p), with the same
/// coefficients as expSO3 (series below 0.03 rad); the de-skewing does it for every point.
inline Eigen::Vector3d expSO3Apply(const Eigen::Vector3d& w, const Eigen::Vector3d& p) {
  const double t2 = w.squaredNorm();
  double a, b;
  if (t2 < 1e-3) {
    a = 1.0 - t2 / 6.0 + t2 * t2 / 120.0;
    b = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;
  } else {
    const double t = std::sqrt(t2);
    a = std::sin(t) / t;
    b = (1.0 - std::cos(t)) / t2;
  }
  const Eigen::Vector3d e = w.cross(p);
  return p + a * e + b * w.cross(e);
}

/// Log: rotation matrix -> rotation vector [rad], angle in [0, pi].
inline Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(R).normalized());
  double angle = aa.angle();
  Eigen::Vector3d axis = aa.axis();
  if (angle > M_PI) {  // Eigen may return (2 pi - a, -axis)
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return angle * axis;
}

/// Right Jacobian Jr(w): Exp(w + d) ~= Exp(w) Exp(Jr(w) d) for small d.
inline Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d W = hat(w);
  if (t2 < 1e-12) return Eigen::Matrix3d::Identity() - 0.5 * W + (1.0 / 6.0) * W * W;
  const double t = std::sqrt(t2);
  return Eigen::Matrix3d::Identity() - ((1.0 - std::cos(t)) / t2) * W + ((t - std::sin(t)) / (t2 * t)) * W * W;
}

/// Inverse of the right Jacobian: Log(Exp(w) Exp(d)) ~= w + Jr^-1(w) d.
inline Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Eigen::Matrix3d W = hat(w);
  if (t2 < 1e-12) return Eigen::Matrix3d::Identity() + 0.5 * W + (1.0 / 12.0) * W * W;
  const double t = std::sqrt(t2);
  return Eigen::Matrix3d::Identity() + 0.5 * W +
         (1.0 / t2 - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t))) * W * W;
}

/// Rotation Rz(yaw) Ry(pitch) Rx(roll).
inline Eigen::Matrix3d rotationFromRpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// (roll, pitch, yaw) of R = Rz(yaw) Ry(pitch) Rx(roll), pitch in [-pi/2, pi/2].
inline Eigen::Vector3d rpyFromRotation(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -R(2, 0))));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return {roll, pitch, yaw};
}

}  // namespace lio
}  // namespace ucon
