#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

#include <Eigen/Dense>

#include "ucon/minco/minco_system.hpp"

using ucon::minco::MincoSystem;

namespace {

// M(T) written densely from the row order documented in minco_system.hpp.
Eigen::MatrixXd denseSystem(const Eigen::VectorXd& T) {
  const int n = static_cast<int>(T.size()), m = 6 * n;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m, m);
  // d-th derivative of sum_j c_{piece,j} t^j: coefficient of c_{piece,j} is j!/(j-d)! t^(j-d).
  auto add = [&](int row, int piece, int d, double t, double sign) {
    for (int j = d; j < 6; ++j) {
      double f = 1.0;
      for (int k = 0; k < d; ++k) f *= j - k;
      M(row, 6 * piece + j) += sign * f * std::pow(t, j - d);
    }
  };
  for (int d = 0; d < 3; ++d) add(d, 0, d, 0.0, 1.0);
  for (int i = 0; i + 1 < n; ++i) {
    const int r = 6 * i + 3;
    add(r + 0, i, 3, T(i), 1.0);  // jerk continuity
    add(r + 0, i + 1, 3, 0.0, -1.0);
    add(r + 1, i, 4, T(i), 1.0);  // snap continuity
    add(r + 1, i + 1, 4, 0.0, -1.0);
    add(r + 2, i, 0, T(i), 1.0);  // waypoint
    for (int d = 0; d < 3; ++d) {  // position, velocity, acceleration continuity
      add(r + 3 + d, i, d, T(i), 1.0);
      add(r + 3 + d, i + 1, d, 0.0, -1.0);
    }
  }
  for (int d = 0; d < 3; ++d) add(m - 3 + d, n - 1, d, T(n - 1), 1.0);
  return M;
}

double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Factorises M(T) in `sys` (already set up for T's size) and solves M x = b and M^T y = b for
// a random b with every row non-zero; returns both relative errors against a dense LU.
std::pair<double, double> solveBothWaysAgainstDense(MincoSystem& sys, const Eigen::VectorXd& T) {
  EXPECT_TRUE(sys.setDurations(T));
  const Eigen::MatrixXd M = denseSystem(T);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(M.rows(), 2);
  MincoSystem::Pairs x = b, y = b;
  sys.solve(x);
  sys.solveTransposed(y);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(M);
  EXPECT_LT((M * Eigen::MatrixXd(x) - b).cwiseAbs().maxCoeff(), 1e-9 * M.cwiseAbs().maxCoeff());
  return {relativeError(x, lu.solve(b)), relativeError(y, lu.transpose().solve(b))};
}

}  // namespace

TEST(MincoSystem, GivenDurationsWhenSolvedBothWaysThenMatchesADenseSolveForAnyRightHandSide) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ut(0.3, 3.0);
  for (int n : {1, 2, 3, 6, 13}) {
    MincoSystem sys;
    sys.setPieces(n);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd T(n);
      for (int i = 0; i < n; ++i) T(i) = ut(rng);
      // The same object again: refactorises in place.
      const auto [forward, transposed] = solveBothWaysAgainstDense(sys, T);
      EXPECT_LT(forward, 1e-11) << "n " << n;
      EXPECT_LT(transposed, 1e-11) << "n " << n;
    }
  }
}

// Elimination without row interchanges loses accuracy when one trajectory mixes short and long
// pieces (measured against a long double solve: about 1e-12 relative for durations within a
// factor 30 of each other, 3e-8 for a factor 3000). This pins the range the planner uses.
TEST(MincoSystem, GivenDurationsAHundredfoldApartWhenSolvedThenStillMatchesADenseSolve) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> log_t(std::log(0.1), std::log(10.0));
  for (int n : {4, 16, 32}) {
    MincoSystem sys;
    sys.setPieces(n);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd T(n);
      for (int i = 0; i < n; ++i) T(i) = std::exp(log_t(rng));
      const auto [forward, transposed] = solveBothWaysAgainstDense(sys, T);
      EXPECT_LT(forward, 1e-10) << "n " << n;
      EXPECT_LT(transposed, 1e-10) << "n " << n;
    }
  }
}

TEST(MincoSystem, GivenTheDocumentedRowsThenTheRowHelpersPointAtThem) {
  MincoSystem sys;
  sys.setPieces(4);
  EXPECT_EQ(MincoSystem::headRow(2), 2);
  EXPECT_EQ(MincoSystem::junctionRow(1), 9);
  EXPECT_EQ(MincoSystem::waypointRow(1), 9 + 2);
  EXPECT_EQ(MincoSystem::kJunctionDerivative[2], 0);
  EXPECT_EQ(sys.tailRow(0), 21);
  EXPECT_EQ(sys.tailRow(2), 23);
}

TEST(MincoSystem, GivenANonFiniteDurationWhenFactorisedThenReportsFailure) {
  MincoSystem sys;
  sys.setPieces(3);
  Eigen::VectorXd T = Eigen::VectorXd::Ones(3);
  T(1) = std::nan("");
  EXPECT_FALSE(sys.setDurations(T));
  T(1) = 1e70;  // T^5 overflows
  EXPECT_FALSE(sys.setDurations(T));
  T(1) = 1.0;
  EXPECT_TRUE(sys.setDurations(T));
}
