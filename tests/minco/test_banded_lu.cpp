#include <gtest/gtest.h>

#include <random>

#include <Eigen/Dense>

#include "ucon/minco/banded_lu.hpp"

using ucon::minco::BandedLu;

TEST(BandedLu, GivenABandedMatrixNeedingPivotingWhenSolvedThenMatchesDenseSolveBothWays) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 23, lower = 4, upper = 3;
  BandedLu lu;
  lu.reset(n, lower, upper);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - lower); j <= std::min(n - 1, i + upper); ++j) {
      // Zero diagonal every third row: plain elimination without pivoting would fail.
      const double v = (i == j && i % 3 == 0) ? 0.0 : u(rng);
      lu(i, j) = v;
      dense(i, j) = v;
    }
  ASSERT_TRUE(lu.factorise());
  Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, 2);
  Eigen::MatrixXd x = b;
  lu.solve(x);
  EXPECT_LT((dense * x - b).cwiseAbs().maxCoeff(), 1e-10);
  Eigen::MatrixXd y = b;
  lu.solveTransposed(y);
  EXPECT_LT((dense.transpose() * y - b).cwiseAbs().maxCoeff(), 1e-10);
  const Eigen::MatrixXd ref = dense.fullPivLu().solve(b);
  EXPECT_LT((ref - x).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(BandedLu, GivenASingularMatrixWhenFactorisedThenReportsFailure) {
  BandedLu lu;
  lu.reset(4, 1, 1);
  lu(0, 0) = 1;
  lu(1, 1) = 1;
  lu(2, 2) = 0;  // row 2 and column 2 empty
  lu(3, 3) = 1;
  EXPECT_FALSE(lu.factorise());
}
