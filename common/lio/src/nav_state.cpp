#include "ucon/lio/nav_state.hpp"

namespace ucon {
namespace lio {

NavState boxplus(const NavState& x, const Vector15& dx) {
  NavState y;
  y.R = x.R * expSO3(dx.segment<3>(kRot));
  y.p = x.p + dx.segment<3>(kPos);
  y.v = x.v + dx.segment<3>(kVel);
  y.bg = x.bg + dx.segment<3>(kBg);
  y.ba = x.ba + dx.segment<3>(kBa);
  return y;
}

Vector15 boxminus(const NavState& a, const NavState& b) {
  Vector15 d;
  d.segment<3>(kRot) = logSO3(b.R.transpose() * a.R);
  d.segment<3>(kPos) = a.p - b.p;
  d.segment<3>(kVel) = a.v - b.v;
  d.segment<3>(kBg) = a.bg - b.bg;
  d.segment<3>(kBa) = a.ba - b.ba;
  return d;
}

Matrix15 boxminusJacobian(const NavState& x, const NavState& ref) {
  Matrix15 J = Matrix15::Identity();
  J.block<3, 3>(kRot, kRot) = rightJacobianInverse(logSO3(ref.R.transpose() * x.R));
  return J;
}

NavState propagate(const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc, double dt,
                   const Eigen::Vector3d& gravity) {
  NavState y = x;
  const Eigen::Vector3d w = gyro - x.bg;
  const Eigen::Vector3d a_world = x.R * (acc - x.ba) + gravity;
  y.R = x.R * expSO3(w * dt);
  y.p = x.p + x.v * dt + 0.5 * a_world * dt * dt;
  y.v = x.v + a_world * dt;
  return y;
}

void transition(const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc, double dt,
                const ImuNoise& noise, Matrix15* F, Matrix15* Qd) {
  const Eigen::Vector3d w = gyro - x.bg;
  const Eigen::Vector3d a = acc - x.ba;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d Jr = rightJacobian(w * dt);
  const Eigen::Matrix3d Ra = x.R * hat(a);
  if (F) {
    F->setIdentity();
    // dtheta' = Exp(w dt)^T dtheta - Jr(w dt) dt dbg
    F->block<3, 3>(kRot, kRot) = expSO3(-w * dt);
    F->block<3, 3>(kRot, kBg) = -Jr * dt;
    // dp' = dp + dt dv - R [a]x dt^2/2 dtheta - R dt^2/2 dba
    F->block<3, 3>(kPos, kVel) = I * dt;
    F->block<3, 3>(kPos, kRot) = -0.5 * Ra * dt * dt;
    F->block<3, 3>(kPos, kBa) = -0.5 * x.R * dt * dt;
    // dv' = dv - R [a]x dt dtheta - R dt dba
    F->block<3, 3>(kVel, kRot) = -Ra * dt;
    F->block<3, 3>(kVel, kBa) = -x.R * dt;
  }
  if (Qd) {
    const double safe_dt = dt > 1e-9 ? dt : 1e-9;
    const double qg = noise.gyro_noise * noise.gyro_noise / safe_dt;
    const double qa = noise.acc_noise * noise.acc_noise / safe_dt;
    const double qbg = noise.gyro_bias_walk * noise.gyro_bias_walk * dt;
    const double qba = noise.acc_bias_walk * noise.acc_bias_walk * dt;
    // G: n_g -> -Jr dt (rotation); n_a -> -R dt^2/2 (position), -R dt (velocity); walks -> I.
    Eigen::Matrix<double, kStateDim, 6> Ga = Eigen::Matrix<double, kStateDim, 6>::Zero();
    Ga.block<3, 3>(kRot, 0) = -Jr * dt;
    Ga.block<3, 3>(kPos, 3) = -0.5 * x.R * dt * dt;
    Ga.block<3, 3>(kVel, 3) = -x.R * dt;
    Eigen::Matrix<double, 6, 1> q;
    q << qg, qg, qg, qa, qa, qa;
    Qd->setZero();
    *Qd = Ga * q.asDiagonal() * Ga.transpose();
    Qd->block<3, 3>(kBg, kBg) += qbg * I;
    Qd->block<3, 3>(kBa, kBa) += qba * I;
  }
}

void propagateCovariance(Matrix15& P, const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc,
                         double dt, const ImuNoise& noise) {
  Matrix15 F, Q;
  transition(x, gyro, acc, dt, noise, &F, &Q);
  P = F * P * F.transpose() + Q;
  P = 0.5 * (P + P.transpose()).eval();
}

}  // namespace lio
}  // namespace ucon
