#pragma once
/// @file nav_state.hpp
/// The state of the LiDAR-inertial filter on SO(3) x R^12 and its IMU motion model
/// (FAST-LIO2, Xu et al. 2022, Sec. III-C "forward propagation").
///
/// State x = (R, p, v, bg, ba): R rotates the IMU frame into the world frame, p and v are the
/// IMU's position [m] and velocity [m/s] in the world frame, bg [rad/s] and ba [m/s^2] the
/// gyro and accelerometer biases. Gravity is a known constant vector in the world frame
/// (z up): the filter does not estimate it (the choice is explained in lio_odometry.hpp).
///
/// Error state dx in R^15, order [dtheta dp dv dbg dba] (kRot, kPos, kVel, kBg, kBa):
/// R = R_hat Exp(dtheta) (body-frame, right perturbation), the rest additive.
///
/// Continuous model with measured rate w_m and specific force a_m:
///   dR/dt = R [w_m - bg - n_g]x,  dp/dt = v,  dv/dt = R (a_m - ba - n_a) + g,
///   dbg/dt = n_bg,  dba/dt = n_ba.
/// Over one step of length dt the measurements are held constant (the caller passes the mean
/// of the two samples that bound the step), which makes the discrete step below exact for
/// that input:
///   R' = R Exp(w dt),  v' = v + (R a + g) dt,  p' = p + v dt + (R a + g) dt^2 / 2,
/// with w = w_m - bg, a = a_m - ba.

#include <Eigen/Core>

#include "ucon/lio/so3.hpp"

namespace ucon {
namespace lio {

constexpr int kStateDim = 15;
constexpr int kRot = 0, kPos = 3, kVel = 6, kBg = 9, kBa = 12;
using Vector15 = Eigen::Matrix<double, kStateDim, 1>;
using Matrix15 = Eigen::Matrix<double, kStateDim, kStateDim>;

/// The filter's state (see the file comment for frames and units).
struct NavState {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< IMU -> world rotation
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      ///< IMU position, world [m]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      ///< IMU velocity, world [m/s]
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();     ///< gyro bias [rad/s]
  Eigen::Vector3d ba = Eigen::Vector3d::Zero();     ///< accelerometer bias [m/s^2]
};

/// x [+] dx: applies an error-state increment (rotation on the right).
NavState boxplus(const NavState& x, const Vector15& dx);
/// a [-] b: the increment d with b [+] d = a (rotation part Log(Rb^T Ra)).
Vector15 boxminus(const NavState& a, const NavState& b);
/// d(x [+] d [-] ref)/dd at d = 0: identity except Jr^-1 of the rotation difference in the
/// rotation block. Used to express the prior of an iterate that has moved away from it.
Matrix15 boxminusJacobian(const NavState& x, const NavState& ref);

/// White-noise densities of the IMU model (continuous time).
struct ImuNoise {
  double gyro_noise = 2e-3;       ///< gyro white noise [rad/s/sqrt(Hz)], > 0
  double acc_noise = 2e-2;        ///< accelerometer white noise [m/s^2/sqrt(Hz)], > 0
  double gyro_bias_walk = 1e-3;   ///< gyro bias random walk [rad/s^2/sqrt(Hz)], > 0
  double acc_bias_walk = 1e-3;    ///< accelerometer bias random walk [m/s^3/sqrt(Hz)], > 0
};

/// One propagation step of `dt` [s] >= 0 with constant measured rate `gyro` [rad/s] and
/// specific force `acc` [m/s^2] (IMU frame); `gravity` is the world-frame vector [m/s^2].
NavState propagate(const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc, double dt,
                   const Eigen::Vector3d& gravity);

/// Error-state transition of the same step: dx' = F dx + G n, n = [n_g n_a n_bg n_ba], and
/// the discrete noise covariance Qd = G diag(q) G^T, with per-step variances gyro_noise^2/dt,
/// acc_noise^2/dt (the noise of a measurement held over dt), gyro_bias_walk^2 dt,
/// acc_bias_walk^2 dt. Either output may be null.
void transition(const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc, double dt,
                const ImuNoise& noise, Matrix15* F, Matrix15* Qd);

/// P' = F P F^T + Qd for the same step, symmetrised.
void propagateCovariance(Matrix15& P, const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc,
                         double dt, const ImuNoise& noise);

}  // namespace lio
}  // namespace ucon
