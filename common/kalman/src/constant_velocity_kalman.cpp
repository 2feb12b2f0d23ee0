#include "ucon/kalman/constant_velocity_kalman.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "ucon/config.hpp"

namespace ucon::kalman {

void KalmanParams::read(ConfigReader& r) {
  r.read("accel_psd_xy", accel_psd_xy, 1e-9, 1e3);
  r.read("accel_psd_z", accel_psd_z, 1e-9, 1e3);
  r.read("position_std", position_std, 1e-6, 10.0);
  r.read("velocity_std", velocity_std, 1e-6, 100.0);
  r.read("initial_velocity_std", initial_velocity_std, 1e-6, 100.0);
  const std::string bad = validate();
  if (!bad.empty()) r.fail(bad, "must be finite and > 0");
}

std::string KalmanParams::validate() const {
  auto ok = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!ok(accel_psd_xy)) return "accel_psd_xy";
  if (!ok(accel_psd_z)) return "accel_psd_z";
  if (!ok(position_std)) return "position_std";
  if (!ok(velocity_std)) return "velocity_std";
  if (!ok(initial_velocity_std)) return "initial_velocity_std";
  return {};
}

const char* toString(KalmanStatus s) {
  switch (s) {
    case KalmanStatus::kOk: return "ok";
    case KalmanStatus::kNotInitialised: return "not_initialised";
    case KalmanStatus::kNonFinite: return "non_finite_input";
    case KalmanStatus::kNegativeDt: return "negative_dt";
    case KalmanStatus::kNotPositiveDefinite: return "not_positive_definite";
    case KalmanStatus::kBadParams: return "bad_params";
  }
  return "unknown";
}

namespace {

double psd(const KalmanParams& p, int axis) { return axis < 2 ? p.accel_psd_xy : p.accel_psd_z; }

void symmetrise(Cov6& P) { P = 0.5 * (P + P.transpose()).eval(); }

}  // namespace

Cov6 processNoise(double dt, const KalmanParams& params) {
  Cov6 Q = Cov6::Zero();
  const double dt2 = dt * dt, dt3 = dt2 * dt;
  for (int a = 0; a < 3; ++a) {
    const double q = psd(params, a);
    Q(a, a) = q * dt3 / 3.0;
    Q(a, a + 3) = Q(a + 3, a) = q * dt2 / 2.0;
    Q(a + 3, a + 3) = q * dt;
  }
  return Q;
}

bool isSymmetricPositiveDefinite(const Cov6& P) {
  if (!P.allFinite()) return false;
  const double scale = P.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) return false;
  if ((P - P.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) return false;
  Eigen::LLT<Cov6> llt(P);
  return llt.info() == Eigen::Success;
}

KalmanStatus predict(const State6& x, const Cov6& P, double dt, const KalmanParams& params,
                     State6* x_out, Cov6* P_out) {
  if (!std::isfinite(dt) || !x.allFinite()) return KalmanStatus::kNonFinite;
  if (dt < 0.0) return KalmanStatus::kNegativeDt;
  if (!params.validate().empty()) return KalmanStatus::kBadParams;
  if (!isSymmetricPositiveDefinite(P)) return KalmanStatus::kNotPositiveDefinite;
  // Eq. (3) with tau = dt; F P F^T + Q(dt) written blockwise (F = [I dt I; 0 I]).
  State6 xn = x;
  xn.head<3>() += dt * x.tail<3>();
  const auto coeffs = covariancePolynomial(P, params);
  Cov6 Pn = coeffs[0] + dt * (coeffs[1] + dt * (coeffs[2] + dt * coeffs[3]));
  symmetrise(Pn);
  if (x_out) *x_out = xn;
  if (P_out) *P_out = Pn;
  return KalmanStatus::kOk;
}

std::array<Cov6, 4> covariancePolynomial(const Cov6& P, const KalmanParams& params) {
  // F P F^T with F = I + dt*S (S shifts velocity into position):
  //   = P + dt (S P + P S^T) + dt^2 S P S^T;  Q(dt) adds q dt^3/3, q dt^2/2, q dt terms.
  std::array<Cov6, 4> c;
  for (auto& m : c) m.setZero();
  c[0] = P;
  const auto Ppv = P.topRightCorner<3, 3>();
  const auto Pvp = P.bottomLeftCorner<3, 3>();
  const auto Pvv = P.bottomRightCorner<3, 3>();
  // dt^1: S P + P S^T.
  c[1].topLeftCorner<3, 3>() = Pvp + Ppv;
  c[1].topRightCorner<3, 3>() = Pvv;
  c[1].bottomLeftCorner<3, 3>() = Pvv;
  // dt^2: S P S^T.
  c[2].topLeftCorner<3, 3>() = Pvv;
  for (int a = 0; a < 3; ++a) {
    const double q = psd(params, a);
    c[1](a + 3, a + 3) += q;
    c[2](a, a + 3) += q / 2.0;
    c[2](a + 3, a) += q / 2.0;
    c[3](a, a) += q / 3.0;
  }
  return c;
}

ConstantVelocityKalman::ConstantVelocityKalman(const KalmanParams& params)
    : params_(params), params_ok_(params.validate().empty()) {}

KalmanStatus ConstantVelocityKalman::init(const Eigen::Vector3d& position,
                                          const Eigen::Vector3d& velocity) {
  State6 x;
  x << position, velocity;
  Cov6 P = Cov6::Zero();
  P.diagonal() << Eigen::Vector3d::Constant(params_.position_std * params_.position_std),
      Eigen::Vector3d::Constant(params_.initial_velocity_std * params_.initial_velocity_std);
  return initState(x, P);
}

KalmanStatus ConstantVelocityKalman::initState(const State6& x, const Cov6& P) {
  if (!params_ok_) return KalmanStatus::kBadParams;
  if (!x.allFinite()) return KalmanStatus::kNonFinite;
  if (!isSymmetricPositiveDefinite(P)) return KalmanStatus::kNotPositiveDefinite;
  x_ = x;
  P_ = P;
  symmetrise(P_);
  initialised_ = true;
  return KalmanStatus::kOk;
}

KalmanStatus ConstantVelocityKalman::predict(double dt) {
  if (!params_ok_) return KalmanStatus::kBadParams;
  if (!initialised_) return KalmanStatus::kNotInitialised;
  return kalman::predict(x_, P_, dt, params_, &x_, &P_);
}

KalmanStatus ConstantVelocityKalman::predicted(double dt, State6* x_out, Cov6* P_out) const {
  if (!params_ok_) return KalmanStatus::kBadParams;
  if (!initialised_) return KalmanStatus::kNotInitialised;
  return kalman::predict(x_, P_, dt, params_, x_out, P_out);
}

namespace {

// Generic update with H selecting the first M state components (M = 6: position and
// velocity, eqs. 4-5 with H = I; M = 3: position only). Joseph form keeps P symmetric PD.
template <int M>
KalmanStatus updateFirst(const Eigen::Matrix<double, M, 1>& z, const Eigen::Matrix<double, M, 1>& r_diag,
                         State6& x, Cov6& P) {
  using MatM = Eigen::Matrix<double, M, M>;
  using Mat6M = Eigen::Matrix<double, 6, M>;
  const MatM S = P.template topLeftCorner<M, M>() + MatM(r_diag.asDiagonal());
  Eigen::LLT<MatM> llt(S);
  if (llt.info() != Eigen::Success) return KalmanStatus::kNotPositiveDefinite;
  const Mat6M PHt = P.template leftCols<M>();
  const Mat6M K = llt.solve(PHt.transpose()).transpose();  // K = P H^T S^-1
  const Eigen::Matrix<double, M, 1> innovation = z - x.template head<M>();
  State6 xn = x + K * innovation;
  Cov6 IKH = Cov6::Identity();
  IKH.template leftCols<M>() -= K;
  Cov6 Pn = IKH * P * IKH.transpose() + K * r_diag.asDiagonal() * K.transpose();
  Pn = 0.5 * (Pn + Pn.transpose()).eval();
  if (!xn.allFinite() || !Pn.allFinite()) return KalmanStatus::kNonFinite;
  x = xn;
  P = Pn;
  return KalmanStatus::kOk;
}

}  // namespace

KalmanStatus ConstantVelocityKalman::update(const Eigen::Vector3d& position,
                                            const Eigen::Vector3d& velocity) {
  if (!params_ok_) return KalmanStatus::kBadParams;
  if (!initialised_) return KalmanStatus::kNotInitialised;
  if (!position.allFinite() || !velocity.allFinite()) return KalmanStatus::kNonFinite;
  State6 z;
  z << position, velocity;
  State6 r;
  r << Eigen::Vector3d::Constant(params_.position_std * params_.position_std),
      Eigen::Vector3d::Constant(params_.velocity_std * params_.velocity_std);
  return updateFirst<6>(z, r, x_, P_);
}

KalmanStatus ConstantVelocityKalman::updatePosition(const Eigen::Vector3d& position) {
  if (!params_ok_) return KalmanStatus::kBadParams;
  if (!initialised_) return KalmanStatus::kNotInitialised;
  if (!position.allFinite()) return KalmanStatus::kNonFinite;
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(params_.position_std * params_.position_std);
  return updateFirst<3>(position, r, x_, P_);
}

}  // namespace ucon::kalman
