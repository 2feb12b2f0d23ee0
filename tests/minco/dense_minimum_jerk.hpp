#pragma once
/// @file dense_minimum_jerk.hpp
/// A straightforward dense reference for ucon::minco::MinimumJerk2D, for tests and the
/// benchmark: the 6N x 6N system is built as a dense matrix in the natural order of the
/// conditions (head p/v/a; per inner waypoint: position, then continuity of derivatives
/// 0..4; tail p/v/a) and solved with Eigen's partial-pivoting LU. The energy is the quadratic
/// form c^T Q(T) c with the Gram matrix of the jerk basis, and the propagation uses a dense
/// dM/dT_i. Slow (O(N^3)) on purpose: it shares no code and no formula layout with the
/// banded implementation it checks.

#include <cmath>

#include <Eigen/Dense>

namespace ucon::minco::testing {

/// Outputs of the full MINCO sequence: solve, energy, energy gradients propagated to the
/// inner waypoints, the durations and the tail position.
struct MincoSequenceResult {
  Eigen::MatrixXd coeffs;        ///< 6N x 2, row 6i + j = c_{i,j}
  double energy = 0.0;           ///< [m^2/s^5]
  Eigen::Matrix2Xd g_inner;      ///< dE/dq, 2 x (N-1)
  Eigen::VectorXd g_durations;   ///< dE/dT (total), N
  Eigen::Vector2d g_tail = Eigen::Vector2d::Zero();  ///< dE/d(tail position)
};

class DenseMinimumJerk2D {
 public:
  using Boundary = Eigen::Matrix<double, 2, 3>;

  /// Runs the whole sequence densely; returns false if the system is singular.
  bool evaluate(const Boundary& head, const Boundary& tail, const Eigen::Matrix2Xd& inner,
                const Eigen::VectorXd& T, MincoSequenceResult* out) {
    const int n = static_cast<int>(T.size());
    const int m = 6 * n;
    M_.setZero(m, m);
    b_.setZero(m, 2);
    // Row of the d-th derivative of the monomial basis at t, for piece `piece`, with sign s.
    auto basisRow = [&](int row, int piece, int d, double t, double s) {
      for (int j = d; j < 6; ++j) M_(row, 6 * piece + j) += s * fall(j, d) * std::pow(t, j - d);
    };
    int row = 0;
    for (int d = 0; d < 3; ++d, ++row) {
      basisRow(row, 0, d, 0.0, 1.0);
      b_.row(row) = head.col(d).transpose();
    }
    for (int i = 0; i + 1 < n; ++i) {
      basisRow(row, i, 0, T(i), 1.0);
      b_.row(row) = inner.col(i).transpose();
      ++row;
      for (int d = 0; d <= 4; ++d, ++row) {
        basisRow(row, i, d, T(i), 1.0);
        basisRow(row, i + 1, d, 0.0, -1.0);
      }
    }
    for (int d = 0; d < 3; ++d, ++row) {
      basisRow(row, n - 1, d, T(n - 1), 1.0);
      b_.row(row) = tail.col(d).transpose();
    }
    lu_.compute(M_);
    if (!(std::abs(lu_.determinant()) > 0.0)) return false;
    out->coeffs = lu_.solve(b_);
    const Eigen::MatrixXd& c = out->coeffs;

    // E = sum_i sum_axis c_i^T Q(T_i) c_i, Q_jk = int_0^T (j)_3 (k)_3 t^(j+k-6) dt.
    Eigen::MatrixXd gC = Eigen::MatrixXd::Zero(m, 2);
    Eigen::VectorXd gT(n);
    out->energy = 0.0;
    for (int i = 0; i < n; ++i) {
      Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
      for (int j = 3; j < 6; ++j)
        for (int k = 3; k < 6; ++k)
          Q(j, k) = fall(j, 3) * fall(k, 3) * std::pow(T(i), j + k - 5) / (j + k - 5);
      const Eigen::Matrix<double, 6, 2> ci = c.block<6, 2>(6 * i, 0);
      out->energy += (ci.transpose() * Q * ci).trace();
      gC.block<6, 2>(6 * i, 0) = 2.0 * Q * ci;
      gT(i) = derivative(c, i, T(i), 3).squaredNorm();  // dE/dT_i with c fixed
    }

    // lambda = M^-T dE/dc; dE/db = lambda; dE/dT_i = gT_i - lambda^T (dM/dT_i) c.
    const Eigen::MatrixXd lambda = lu_.transpose().solve(gC);
    out->g_inner.resize(2, n - 1);
    out->g_durations.resize(n);
    for (int i = 0; i + 1 < n; ++i) out->g_inner.col(i) = lambda.row(3 + 6 * i).transpose();
    out->g_tail = lambda.row(m - 3).transpose();
    for (int i = 0; i < n; ++i) {
      dM_.setZero(m, m);
      const int first = (i + 1 < n) ? 3 + 6 * i : m - 3;
      const int rows = (i + 1 < n) ? 6 : 3;
      for (int r = 0; r < rows; ++r) {
        const int d = (i + 1 < n) ? (r == 0 ? 0 : r - 1) : r;
        for (int j = d + 1; j < 6; ++j)
          dM_(first + r, 6 * i + j) = fall(j, d) * (j - d) * std::pow(T(i), j - d - 1);
      }
      out->g_durations(i) = gT(i) - (lambda.transpose() * dM_ * c).trace();
    }
    return true;
  }

  /// d-th derivative of piece i at local time t.
  static Eigen::Vector2d derivative(const Eigen::MatrixXd& c, int i, double t, int d) {
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    for (int j = d; j < 6; ++j) v += fall(j, d) * std::pow(t, j - d) * c.row(6 * i + j).transpose();
    return v;
  }

 private:
  // j! / (j - d)!
  static double fall(int j, int d) {
    double f = 1.0;
    for (int k = 0; k < d; ++k) f *= j - k;
    return f;
  }

  Eigen::MatrixXd M_, dM_, b_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

/// max |a - b| / max |b| (normwise relative difference, 0 for two zero arrays).
template <typename A, typename B>
double relativeDifference(const A& a, const B& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  const double diff = (a - b).cwiseAbs().maxCoeff();
  return scale > 0.0 ? diff / scale : diff;
}

}  // namespace ucon::minco::testing
