#include "ucon/minco/minimum_jerk.hpp"

#include <algorithm>
#include <cmath>

namespace ucon::minco {

namespace {

// j! / (j - d)!: coefficient of t^(j-d) in the d-th derivative of t^j.
constexpr double kFall[6][6] = {
    {1, 0, 0, 0, 0, 0},   {1, 1, 0, 0, 0, 0},    {1, 2, 2, 0, 0, 0},
    {1, 3, 6, 6, 0, 0},   {1, 4, 12, 24, 24, 0}, {1, 5, 20, 60, 120, 120}};

// Powers 1, T, ..., T^5.
inline void powers(double T, double* p) {
  p[0] = 1.0;
  for (int k = 1; k < 6; ++k) p[k] = p[k - 1] * T;
}

}  // namespace

bool MinimumJerk2D::setConditions(const Boundary& head, const Boundary& tail, int pieces) {
  if (pieces < 1 || !head.allFinite() || !tail.allFinite()) return false;
  head_ = head;
  tail_ = tail;
  if (pieces != n_) {
    n_ = pieces;
    T_ = Eigen::VectorXd::Ones(n_);
    c_ = Eigen::MatrixXd::Zero(6 * n_, 2);
    system_.setPieces(n_);
    rhs_ = MincoSystem::Pairs::Zero(6 * n_, 2);
    adjoint_ = MincoSystem::Pairs::Zero(6 * n_, 2);
  }
  return true;
}

bool MinimumJerk2D::setTail(const Boundary& tail) {
  if (n_ < 1 || !tail.allFinite()) return false;
  tail_ = tail;
  return true;
}

bool MinimumJerk2D::setParameters(const Eigen::Ref<const Eigen::Matrix2Xd>& inner,
                                  const Eigen::Ref<const Eigen::VectorXd>& durations) {
  if (n_ < 1 || inner.cols() != n_ - 1 || durations.size() != n_) return false;
  if (!inner.allFinite() || !durations.allFinite() || !(durations.minCoeff() > 0.0)) return false;
  T_ = durations;
  if (!system_.setDurations(T_)) return false;
  // b(q): head p/v/a, the waypoints, tail p/v/a; the continuity rows are zero.
  rhs_.setZero();
  for (int d = 0; d < 3; ++d) {
    rhs_.row(MincoSystem::headRow(d)) = head_.col(d).transpose();
    rhs_.row(system_.tailRow(d)) = tail_.col(d).transpose();
  }
  for (int i = 0; i + 1 < n_; ++i) rhs_.row(MincoSystem::waypointRow(i)) = inner.col(i).transpose();
  system_.solve(rhs_);
  c_ = rhs_;
  return c_.allFinite();
}

double MinimumJerk2D::energy() const {
  double e = 0.0;
  for (int i = 0; i < n_; ++i) {
    double tp[6];
    powers(T_(i), tp);
    const Eigen::RowVector2d c3 = c_.row(6 * i + 3), c4 = c_.row(6 * i + 4), c5 = c_.row(6 * i + 5);
    // int_0^T ||6 c3 + 24 c4 t + 60 c5 t^2||^2 dt
    e += 36.0 * c3.squaredNorm() * tp[1] + 144.0 * c3.dot(c4) * tp[2] +
         (192.0 * c4.squaredNorm() + 240.0 * c3.dot(c5)) * tp[3] + 720.0 * c4.dot(c5) * tp[4] +
         720.0 * c5.squaredNorm() * tp[5];
  }
  return e;
}

void MinimumJerk2D::addEnergyGradient(Eigen::Ref<Eigen::MatrixXd> gC,
                                      Eigen::Ref<Eigen::VectorXd> gT) const {
  for (int i = 0; i < n_; ++i) {
    double tp[6];
    powers(T_(i), tp);
    const Eigen::RowVector2d c3 = c_.row(6 * i + 3), c4 = c_.row(6 * i + 4), c5 = c_.row(6 * i + 5);
    gC.row(6 * i + 3) += 72.0 * c3 * tp[1] + 144.0 * c4 * tp[2] + 240.0 * c5 * tp[3];
    gC.row(6 * i + 4) += 144.0 * c3 * tp[2] + 384.0 * c4 * tp[3] + 720.0 * c5 * tp[4];
    gC.row(6 * i + 5) += 240.0 * c3 * tp[3] + 720.0 * c4 * tp[4] + 1440.0 * c5 * tp[5];
    // dE/dT = ||p'''(T)||^2
    const Eigen::RowVector2d jerk = 6.0 * c3 + 24.0 * c4 * tp[1] + 60.0 * c5 * tp[2];
    gT(i) += jerk.squaredNorm();
  }
}

void MinimumJerk2D::propagateGradient(const Eigen::Ref<const Eigen::MatrixXd>& gC,
                                      const Eigen::Ref<const Eigen::VectorXd>& gT,
                                      Eigen::Ref<Eigen::Matrix2Xd> g_inner,
                                      Eigen::Ref<Eigen::VectorXd> g_durations,
                                      Eigen::Vector2d* g_tail_position) {
  // K(c(q,T), T): dK/db = M^-T dK/dc =: lambda; dK/dT_i = gT_i - lambda^T (dM/dT_i) c.
  adjoint_ = gC;
  system_.solveTransposed(adjoint_);
  for (int i = 0; i + 1 < n_; ++i) g_inner.col(i) = adjoint_.row(MincoSystem::waypointRow(i)).transpose();
  if (g_tail_position) *g_tail_position = adjoint_.row(system_.tailRow(0)).transpose();
  for (int i = 0; i < n_; ++i) {
    // Row of derivative order d of piece i at T_i: d/dT_i (row . c) = p_i^(d+1)(T_i).
    Eigen::Vector2d deriv[6];
    for (int d = 1; d <= 5; ++d) deriv[d] = derivative(i, T_(i), d);
    double g = gT(i);
    if (i + 1 < n_) {
      const int r = MincoSystem::junctionRow(i);
      for (int k = 0; k < 6; ++k)
        g -= adjoint_.row(r + k).dot(deriv[MincoSystem::kJunctionDerivative[k] + 1].transpose());
    } else {
      for (int d = 0; d < 3; ++d) g -= adjoint_.row(system_.tailRow(d)).dot(deriv[d + 1].transpose());
    }
    g_durations(i) = g;
  }
}

Eigen::Vector2d MinimumJerk2D::derivative(int piece, double t, int order) const {
  Eigen::Vector2d out = Eigen::Vector2d::Zero();
  if (order > 5 || order < 0) return out;
  // Horner over the derivative's coefficients.
  for (int j = 5; j >= order; --j)
    out = out * t + kFall[j][order] * c_.row(6 * piece + j).transpose();
  return out;
}

Eigen::Vector2d MinimumJerk2D::derivativeAt(double t, int order) const {
  t = std::max(0.0, t);
  for (int i = 0; i < n_; ++i) {
    if (t <= T_(i) || i + 1 == n_) return derivative(i, std::min(t, T_(i)), order);
    t -= T_(i);
  }
  return Eigen::Vector2d::Zero();
}

void MinimumJerk2D::toTrajectory(int64_t start_utime, trajectory_t* out) const {
  out->start_utime = start_utime;
  out->dim = 2;
  out->order1 = 6;
  out->num_pieces = n_;
  out->durations.assign(T_.data(), T_.data() + n_);
  out->num_coeffs = n_ * 2 * 6;
  out->coeffs.resize(static_cast<std::size_t>(out->num_coeffs));
  for (int k = 0; k < n_; ++k)
    for (int d = 0; d < 2; ++d)
      for (int j = 0; j < 6; ++j) out->coeffs[(k * 2 + d) * 6 + j] = c_(6 * k + j, d);
}

}  // namespace ucon::minco
