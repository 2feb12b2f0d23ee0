#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dense_minimum_jerk.hpp"
#include "ucon/minco/minimum_jerk.hpp"
#include "ucon/minco/time_map.hpp"

using ucon::minco::MinimumJerk2D;

namespace {

struct Problem {
  MinimumJerk2D::Boundary head, tail;
  Eigen::Matrix2Xd inner;
  Eigen::VectorXd T;
};

Problem randomProblem(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), ut(0.4, 2.0);
  Problem p;
  p.head << 0, u(rng), u(rng), 0, u(rng), u(rng);
  p.tail << 3.0 * n, u(rng), u(rng), 1.0, u(rng), u(rng);
  p.inner.resize(2, n - 1);
  for (int i = 0; i + 1 < n; ++i) p.inner.col(i) << 3.0 * (i + 1) + u(rng), u(rng);
  p.T.resize(n);
  for (int i = 0; i < n; ++i) p.T(i) = ut(rng);
  return p;
}

double relErr(double a, double b) { return std::abs(a - b) / std::max(1e-8, std::max(std::abs(a), std::abs(b))); }

}  // namespace

TEST(MinimumJerk, GivenWaypointsAndBoundariesThenTrajectoryPassesThroughAndIsC4) {
  const int n = 6;
  const Problem pr = randomProblem(n, 7);
  MinimumJerk2D mj;
  ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, n));
  ASSERT_TRUE(mj.setParameters(pr.inner, pr.T));
  for (int d = 0; d < 3; ++d) {
    EXPECT_LT((mj.derivative(0, 0.0, d) - pr.head.col(d)).norm(), 1e-9) << d;
    EXPECT_LT((mj.derivative(n - 1, pr.T(n - 1), d) - pr.tail.col(d)).norm(), 1e-8) << d;
  }
  for (int i = 0; i + 1 < n; ++i) {
    EXPECT_LT((mj.derivative(i, pr.T(i), 0) - pr.inner.col(i)).norm(), 1e-9);
    for (int d = 0; d <= 4; ++d) {
      const Eigen::Vector2d l = mj.derivative(i, pr.T(i), d), r = mj.derivative(i + 1, 0.0, d);
      EXPECT_LT((l - r).norm(), 1e-7 * (1.0 + l.norm())) << "junction " << i << " order " << d;
    }
  }
  // The 5th derivative is generally discontinuous (s = 3 gives C^4, not C^5).
  EXPECT_GT((mj.derivative(0, pr.T(0), 5) - mj.derivative(1, 0.0, 5)).norm(), 1e-6);
}

TEST(MinimumJerk, GivenOnePieceRestToRestThenMatchesTheClassicQuinticProfile) {
  MinimumJerk2D mj;
  MinimumJerk2D::Boundary head = MinimumJerk2D::Boundary::Zero(), tail = MinimumJerk2D::Boundary::Zero();
  tail.col(0) << 2.0, -1.0;
  ASSERT_TRUE(mj.setConditions(head, tail, 1));
  Eigen::VectorXd T(1);
  T << 2.0;
  ASSERT_TRUE(mj.setParameters(Eigen::Matrix2Xd(2, 0), T));
  for (double t : {0.3, 1.0, 1.7}) {
    const double s = t / 2.0;
    const double shape = 10 * s * s * s - 15 * s * s * s * s + 6 * s * s * s * s * s;
    EXPECT_NEAR(mj.derivative(0, t, 0)(0), 2.0 * shape, 1e-12);
    EXPECT_NEAR(mj.derivative(0, t, 0)(1), -1.0 * shape, 1e-12);
  }
  // Energy of x = D (10s^3 - 15s^4 + 6s^5) over T: 720 D^2 / T^5.
  EXPECT_NEAR(mj.energy(), 720.0 * (4.0 + 1.0) / 32.0, 1e-9);
}

TEST(MinimumJerk, GivenATrajectoryThenClosedFormEnergyEqualsNumericalIntegral) {
  const int n = 5;
  const Problem pr = randomProblem(n, 11);
  MinimumJerk2D mj;
  ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, n));
  ASSERT_TRUE(mj.setParameters(pr.inner, pr.T));
  double numeric = 0.0;
  const int m = 2000;  // composite Simpson per piece: exact for the degree-4 integrand
  for (int i = 0; i < n; ++i) {
    const double h = pr.T(i) / m;
    for (int k = 0; k <= m; ++k) {
      const double w = (k == 0 || k == m) ? 1.0 : (k % 2 ? 4.0 : 2.0);
      numeric += w * h / 3.0 * mj.derivative(i, k * h, 3).squaredNorm();
    }
  }
  EXPECT_LT(relErr(mj.energy(), numeric), 1e-10);
}

TEST(MinimumJerk, GivenEnergyWhenDifferentiatedThenMatchesFiniteDifferences) {
  const int n = 5;
  const Problem pr = randomProblem(n, 13);
  MinimumJerk2D mj;
  ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, n));
  auto energyAt = [&](const Eigen::Matrix2Xd& q, const Eigen::VectorXd& T) {
    MinimumJerk2D m2;
    m2.setConditions(pr.head, pr.tail, n);
    m2.setParameters(q, T);
    return m2.energy();
  };
  ASSERT_TRUE(mj.setParameters(pr.inner, pr.T));
  Eigen::MatrixXd gC = Eigen::MatrixXd::Zero(6 * n, 2);
  Eigen::VectorXd gT = Eigen::VectorXd::Zero(n);
  mj.addEnergyGradient(gC, gT);
  // Partial gradient w.r.t. c and T (c fixed): check dE/dT_i = ||p'''(T_i)||^2 and dE/dc by FD on the closed form.
  for (int i = 0; i < n; ++i) EXPECT_LT(relErr(gT(i), mj.derivative(i, pr.T(i), 3).squaredNorm()), 1e-12);
  Eigen::Matrix2Xd gq(2, n - 1);
  Eigen::VectorXd gTot(n);
  mj.propagateGradient(gC, gT, gq, gTot);
  const double eps = 1e-6;
  for (int i = 0; i + 1 < n; ++i)
    for (int d = 0; d < 2; ++d) {
      Eigen::Matrix2Xd qp = pr.inner, qm = pr.inner;
      qp(d, i) += eps;
      qm(d, i) -= eps;
      const double fd = (energyAt(qp, pr.T) - energyAt(qm, pr.T)) / (2 * eps);
      EXPECT_LT(relErr(gq(d, i), fd), 1e-5) << i << "," << d << " " << gq(d, i) << " vs " << fd;
    }
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd Tp = pr.T, Tm = pr.T;
    Tp(i) += eps;
    Tm(i) -= eps;
    const double fd = (energyAt(pr.inner, Tp) - energyAt(pr.inner, Tm)) / (2 * eps);
    EXPECT_LT(relErr(gTot(i), fd), 1e-5) << i << " " << gTot(i) << " vs " << fd;
  }
}

TEST(MinimumJerk, GivenAnArbitraryCostOfCoefficientsAndTimesThenPropagatedGradientMatchesFiniteDifferences) {
  const int n = 4;
  const Problem pr = randomProblem(n, 17);
  // K(c, T) = sum_i sum_j w_ij * ||p_i(s_j T_i)||^2 + sum_i T_i^3 (depends on c and explicitly on T).
  const double s[3] = {0.2, 0.5, 0.9};
  auto cost = [&](const MinimumJerk2D& m, Eigen::MatrixXd* gC, Eigen::VectorXd* gT) {
    double k = 0.0;
    for (int i = 0; i < m.pieces(); ++i) {
      const double Ti = m.durations()(i);
      for (int j = 0; j < 3; ++j) {
        const double t = s[j] * Ti;
        const Eigen::Vector2d p = m.derivative(i, t, 0);
        k += (j + 1) * p.squaredNorm();
        if (gC) {
          double tp = 1.0;
          for (int a = 0; a < 6; ++a, tp *= t) gC->row(6 * i + a) += (j + 1) * 2.0 * tp * p.transpose();
          (*gT)(i) += (j + 1) * 2.0 * p.dot(m.derivative(i, t, 1)) * s[j];
        }
      }
      k += Ti * Ti * Ti;
      if (gT) (*gT)(i) += 3 * Ti * Ti;
    }
    return k;
  };
  auto total = [&](const Eigen::Matrix2Xd& q, const Eigen::VectorXd& T, const Eigen::Vector2d& tailp) {
    MinimumJerk2D m;
    MinimumJerk2D::Boundary tail = pr.tail;
    tail.col(0) = tailp;
    m.setConditions(pr.head, tail, n);
    m.setParameters(q, T);
    return cost(m, nullptr, nullptr);
  };
  MinimumJerk2D mj;
  ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, n));
  ASSERT_TRUE(mj.setParameters(pr.inner, pr.T));
  Eigen::MatrixXd gC = Eigen::MatrixXd::Zero(6 * n, 2);
  Eigen::VectorXd gT = Eigen::VectorXd::Zero(n);
  cost(mj, &gC, &gT);
  Eigen::Matrix2Xd gq(2, n - 1);
  Eigen::VectorXd gTot(n);
  Eigen::Vector2d gTail;
  mj.propagateGradient(gC, gT, gq, gTot, &gTail);
  const double eps = 1e-6;
  const Eigen::Vector2d tp0 = pr.tail.col(0);
  for (int i = 0; i + 1 < n; ++i)
    for (int d = 0; d < 2; ++d) {
      Eigen::Matrix2Xd qp = pr.inner, qm = pr.inner;
      qp(d, i) += eps;
      qm(d, i) -= eps;
      const double fd = (total(qp, pr.T, tp0) - total(qm, pr.T, tp0)) / (2 * eps);
      EXPECT_LT(relErr(gq(d, i), fd), 1e-5) << gq(d, i) << " vs " << fd;
    }
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd Tp = pr.T, Tm = pr.T;
    Tp(i) += eps;
    Tm(i) -= eps;
    const double fd = (total(pr.inner, Tp, tp0) - total(pr.inner, Tm, tp0)) / (2 * eps);
    EXPECT_LT(relErr(gTot(i), fd), 1e-5) << gTot(i) << " vs " << fd;
  }
  for (int d = 0; d < 2; ++d) {
    Eigen::Vector2d a = tp0, b = tp0;
    a(d) += eps;
    b(d) -= eps;
    const double fd = (total(pr.inner, pr.T, a) - total(pr.inner, pr.T, b)) / (2 * eps);
    EXPECT_LT(relErr(gTail(d), fd), 1e-5);
  }
}

TEST(MinimumJerk, GivenRandomProblemsWhenTheSequenceRunsThenEveryOutputMatchesTheDenseReference) {
  using namespace ucon::minco::testing;
  for (int n : {1, 2, 3, 7, 16}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const Problem pr = randomProblem(n, 100 * n + seed);
      MinimumJerk2D mj;
      ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, n));
      ASSERT_TRUE(mj.setParameters(pr.inner, pr.T));
      Eigen::MatrixXd gC = Eigen::MatrixXd::Zero(6 * n, 2);
      Eigen::VectorXd gT = Eigen::VectorXd::Zero(n), g_durations(n);
      Eigen::Matrix2Xd g_inner(2, n - 1);
      Eigen::Vector2d g_tail;
      const double energy = mj.energy();
      mj.addEnergyGradient(gC, gT);
      mj.propagateGradient(gC, gT, g_inner, g_durations, &g_tail);
      DenseMinimumJerk2D dense;
      MincoSequenceResult ref;
      ASSERT_TRUE(dense.evaluate(pr.head, pr.tail, pr.inner, pr.T, &ref));
      EXPECT_LT(relativeDifference(mj.coeffs(), ref.coeffs), 1e-12) << n << "/" << seed;
      EXPECT_LT(relErr(energy, ref.energy), 1e-12) << n << "/" << seed;
      if (n > 1) {
        EXPECT_LT(relativeDifference(g_inner, ref.g_inner), 1e-12) << n << "/" << seed;
      }
      EXPECT_LT(relativeDifference(g_durations, ref.g_durations), 1e-12) << n << "/" << seed;
      EXPECT_LT(relativeDifference(g_tail, ref.g_tail), 1e-12) << n << "/" << seed;
    }
  }
}

TEST(MinimumJerk, GivenATrajectoryWhenWrittenToAMessageThenCoefficientLayoutEvaluatesTheSame) {
  const int n = 3;
  const Problem pr = randomProblem(n, 19);
  MinimumJerk2D mj;
  ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, n));
  ASSERT_TRUE(mj.setParameters(pr.inner, pr.T));
  ucon::trajectory_t msg;
  mj.toTrajectory(123456, &msg);
  EXPECT_EQ(msg.start_utime, 123456);
  EXPECT_EQ(msg.dim, 2);
  EXPECT_EQ(msg.order1, 6);
  ASSERT_EQ(msg.num_pieces, n);
  ASSERT_EQ(msg.num_coeffs, n * 12);
  ASSERT_EQ(static_cast<int>(msg.coeffs.size()), n * 12);
  for (int k = 0; k < n; ++k) {
    EXPECT_DOUBLE_EQ(msg.durations[k], pr.T(k));
    const double t = 0.37 * pr.T(k);
    for (int d = 0; d < 2; ++d) {
      double v = 0.0, tp = 1.0;
      for (int j = 0; j < 6; ++j, tp *= t) v += msg.coeffs[(k * msg.dim + d) * msg.order1 + j] * tp;
      EXPECT_NEAR(v, mj.derivative(k, t, 0)(d), 1e-12);
    }
  }
  const double t_global = pr.T(0) + 0.5 * pr.T(1);
  EXPECT_LT((mj.derivativeAt(t_global, 1) - mj.derivative(1, 0.5 * pr.T(1), 1)).norm(), 1e-12);
}

TEST(MinimumJerk, GivenBadParametersThenSetParametersFailsWithoutCrashing) {
  const Problem pr = randomProblem(3, 23);
  MinimumJerk2D mj;
  EXPECT_FALSE(mj.setConditions(pr.head, pr.tail, 0));
  ASSERT_TRUE(mj.setConditions(pr.head, pr.tail, 3));
  Eigen::VectorXd T = pr.T;
  T(1) = 0.0;
  EXPECT_FALSE(mj.setParameters(pr.inner, T));
  T(1) = std::nan("");
  EXPECT_FALSE(mj.setParameters(pr.inner, T));
  T(1) = 1e70;  // T^5 overflows: the system is not finite
  EXPECT_FALSE(mj.setParameters(pr.inner, T));
  EXPECT_TRUE(mj.setParameters(pr.inner, pr.T));  // and the next call works again
  EXPECT_FALSE(mj.setParameters(Eigen::Matrix2Xd::Zero(2, 5), pr.T));
  MinimumJerk2D::Boundary bad = pr.head;
  bad(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(mj.setConditions(bad, pr.tail, 3));
}

TEST(TimeMap, GivenAnyTauThenDurationPositiveInverseRoundTripsAndDerivativeMatchesFiniteDifference) {
  using namespace ucon::minco;
  EXPECT_DOUBLE_EQ(durationFromTau(0.0), 1.0);
  EXPECT_NEAR(durationFromTau(2.0), 5.0, 1e-15);          // 2 + 2 + 1
  EXPECT_NEAR(durationFromTau(-2.0), 1.0 / 5.0, 1e-15);   // 1/(2 + 2 + 1)
  for (double tau : {-30.0, -3.0, -0.7, -1e-3, 1e-3, 0.4, 2.5, 40.0}) {
    const double T = durationFromTau(tau);
    EXPECT_GT(T, 0.0);
    EXPECT_NEAR(tauFromDuration(T), tau, 1e-9 * (1 + std::abs(tau)));
    const double h = 1e-6;
    const double fd = (durationFromTau(tau + h) - durationFromTau(tau - h)) / (2 * h);
    EXPECT_LT(std::abs(fd - durationDerivative(tau)) / std::abs(fd), 1e-6) << tau;
  }
}
