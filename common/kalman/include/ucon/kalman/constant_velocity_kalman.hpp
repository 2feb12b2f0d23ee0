#pragma once
/// @file constant_velocity_kalman.hpp
/// 6-state constant-velocity Kalman filter over [x y z vx vy vz] (paper Sec. IV-A, eqs. 3-5),
/// with a closed-form prediction of state and full covariance to any future time.
///
/// Process model: continuous white acceleration with spectral density q per axis, so the
/// discrete model over any dt is exact and consistent (predicting dt1 then dt2 equals
/// predicting dt1 + dt2):
///   F(dt) = [I dt*I; 0 I],  Q(dt) per axis = q * [dt^3/3 dt^2/2; dt^2/2 dt].
/// Measurement: position and differenced velocity (H = I, as in the paper), R diagonal.
/// Units: m, m/s, s. Covariance blocks in m^2, m^2/s, m^2/s^2.

#include <array>
#include <string>

#include <Eigen/Core>

namespace ucon {
class ConfigReader;
}

namespace ucon::kalman {

using State6 = Eigen::Matrix<double, 6, 1>;
using Cov6 = Eigen::Matrix<double, 6, 6>;

/// Noise parameters of the filter (YAML keys are the field names without the trailing _).
struct KalmanParams {
  double accel_psd_xy = 0.5;        ///< white-acceleration spectral density, x and y [m^2/s^3], > 0
  double accel_psd_z = 0.05;        ///< white-acceleration spectral density, z [m^2/s^3], > 0
  double position_std = 0.05;       ///< measured position noise (1 sigma) [m], > 0
  /// Measured (differenced) velocity noise (1 sigma) [m/s], > 0. A difference of two positions
  /// dt apart has noise sqrt(2)*position_std/dt (3.5 m/s at 5 cm and 50 Hz): set it accordingly.
  double velocity_std = 0.3;
  double initial_velocity_std = 1.0; ///< velocity uncertainty of a new track (1 sigma) [m/s], > 0

  /// Keys: accel_psd_xy, accel_psd_z, position_std, velocity_std, initial_velocity_std.
  void read(ConfigReader& r);
  /// Empty when valid, otherwise the name of the first bad field.
  std::string validate() const;
};

/// Result of a filter operation. Operations that fail leave the filter unchanged.
enum class KalmanStatus {
  kOk = 0,
  kNotInitialised,     ///< predict/update before init
  kNonFinite,          ///< NaN or Inf in an input
  kNegativeDt,         ///< dt < 0 (time going backwards)
  kNotPositiveDefinite,///< a covariance (input or innovation) is not symmetric positive definite
  kBadParams,          ///< KalmanParams::validate() failed
};
const char* toString(KalmanStatus s);

/// Closed-form process noise Q(dt) of the white-acceleration model [m^2, m^2/s, m^2/s^2].
Cov6 processNoise(double dt, const KalmanParams& params);

/// Predicts state and full covariance `dt` seconds ahead (dt >= 0):
/// x(dt) = F(dt) x,  P(dt) = F(dt) P F(dt)^T + Q(dt).
/// The one prediction function shared by tracking and planning. Returns kNonFinite,
/// kNegativeDt or kNotPositiveDefinite (P not symmetric PD) and leaves outputs untouched then.
KalmanStatus predict(const State6& x, const Cov6& P, double dt, const KalmanParams& params,
                     State6* x_out, Cov6* P_out);

/// The same prediction as a polynomial in dt, for callers that evaluate it many times:
/// P(dt) = P0 + dt*P1 + dt^2*P2 + dt^3*P3 (exact, not an approximation), so dP/dt is
/// available in closed form too. coeffs[k] = Pk.
std::array<Cov6, 4> covariancePolynomial(const Cov6& P, const KalmanParams& params);

/// True if P is finite, symmetric (relative 1e-9) and positive definite.
bool isSymmetricPositiveDefinite(const Cov6& P);

/// One tracked object's filter.
class ConstantVelocityKalman {
 public:
  explicit ConstantVelocityKalman(const KalmanParams& params = KalmanParams());

  /// Starts from a measured position and velocity; P0 = diag(position_std^2 (3),
  /// initial_velocity_std^2 (3)).
  KalmanStatus init(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity);
  /// Starts from an explicit state and covariance (must be symmetric PD).
  KalmanStatus initState(const State6& x, const Cov6& P);

  /// Time update by dt >= 0 seconds (dt = 0 is a no-op).
  KalmanStatus predict(double dt);
  /// Measurement update with position [m] and differenced velocity [m/s] (H = I).
  KalmanStatus update(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity);
  /// Measurement update with position only (first frame of a track, no velocity yet).
  KalmanStatus updatePosition(const Eigen::Vector3d& position);

  /// State and covariance `dt` seconds after the filter's current time, without changing it.
  KalmanStatus predicted(double dt, State6* x_out, Cov6* P_out) const;

  bool initialised() const { return initialised_; }
  const State6& state() const { return x_; }
  const Cov6& covariance() const { return P_; }
  const KalmanParams& params() const { return params_; }

 private:
  KalmanParams params_;
  bool params_ok_;
  bool initialised_ = false;
  State6 x_ = State6::Zero();
  Cov6 P_ = Cov6::Identity();
};

}  // namespace ucon::kalman
