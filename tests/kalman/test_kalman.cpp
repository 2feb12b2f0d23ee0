#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Eigenvalues>

#include "ucon/config.hpp"
#include "ucon/kalman/constant_velocity_kalman.hpp"

using namespace ucon::kalman;

namespace {

Cov6 randomSpd(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Cov6 A;
  for (int i = 0; i < 36; ++i) A(i) = n(rng);
  return A * A.transpose() + 0.1 * Cov6::Identity();
}

double positionTrace(const Cov6& P) { return P.topLeftCorner<3, 3>().trace(); }

}  // namespace

TEST(Kalman, GivenAStateWhenPredictedThenMatchesFPFtPlusQClosedForm) {
  std::mt19937 rng(3);
  KalmanParams params;
  params.accel_psd_xy = 0.7;
  params.accel_psd_z = 0.2;
  const Cov6 P = randomSpd(rng);
  State6 x;
  x << 1, 2, 3, 0.5, -0.25, 0.1;
  const double dt = 0.37;
  State6 xn;
  Cov6 Pn;
  ASSERT_EQ(predict(x, P, dt, params, &xn, &Pn), KalmanStatus::kOk);

  Cov6 F = Cov6::Identity();
  F.topRightCorner<3, 3>() = dt * Eigen::Matrix3d::Identity();
  Cov6 Q = Cov6::Zero();  // hand-written white-acceleration noise
  const double qs[3] = {0.7, 0.7, 0.2};
  for (int a = 0; a < 3; ++a) {
    Q(a, a) = qs[a] * dt * dt * dt / 3;
    Q(a, a + 3) = Q(a + 3, a) = qs[a] * dt * dt / 2;
    Q(a + 3, a + 3) = qs[a] * dt;
  }
  const Cov6 expected = F * P * F.transpose() + Q;
  EXPECT_LT((Pn - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((xn - F * x).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(xn(0), 1 + 0.5 * dt, 1e-14);
  EXPECT_LT((processNoise(dt, params) - Q).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(Kalman, GivenTwoStepsWhenPredictedThenEqualsOneStepOfTheSum) {
  std::mt19937 rng(5);
  KalmanParams params;
  const Cov6 P = randomSpd(rng);
  State6 x = State6::Random();
  State6 x1, x2, x12;
  Cov6 P1, P2, P12;
  ASSERT_EQ(predict(x, P, 0.2, params, &x1, &P1), KalmanStatus::kOk);
  ASSERT_EQ(predict(x1, P1, 0.5, params, &x2, &P2), KalmanStatus::kOk);
  ASSERT_EQ(predict(x, P, 0.7, params, &x12, &P12), KalmanStatus::kOk);
  EXPECT_LT((P2 - P12).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((x2 - x12).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Kalman, GivenCovariancePolynomialThenItEqualsPredictionAtAnyDt) {
  std::mt19937 rng(7);
  KalmanParams params;
  const Cov6 P = randomSpd(rng);
  const auto c = covariancePolynomial(P, params);
  for (double dt : {0.0, 0.05, 1.3, 4.0}) {
    Cov6 Pn;
    ASSERT_EQ(predict(State6::Zero(), P, dt, params, nullptr, &Pn), KalmanStatus::kOk);
    const Cov6 poly = c[0] + dt * c[1] + dt * dt * c[2] + dt * dt * dt * c[3];
    EXPECT_LT((poly - Pn).cwiseAbs().maxCoeff(), 1e-12 * (1 + Pn.cwiseAbs().maxCoeff()));
  }
}

TEST(Kalman, GivenATrackWhenCoastingThenCovarianceGrowsAndWhenUpdatedThenShrinks) {
  ConstantVelocityKalman kf;
  ASSERT_EQ(kf.init(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)), KalmanStatus::kOk);
  double prev = positionTrace(kf.covariance());
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(kf.predict(0.02), KalmanStatus::kOk);
    const double now = positionTrace(kf.covariance());
    EXPECT_GT(now, prev);
    prev = now;
    EXPECT_TRUE(isSymmetricPositiveDefinite(kf.covariance()));
  }
  const Cov6 before = kf.covariance();
  ASSERT_EQ(kf.update(Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(1, 0, 0)), KalmanStatus::kOk);
  EXPECT_LT(positionTrace(kf.covariance()), positionTrace(before));
  const double vel_after = kf.covariance().bottomRightCorner<3, 3>().trace();
  const double vel_before = before.bottomRightCorner<3, 3>().trace();
  EXPECT_LT(vel_after, vel_before);
  // P_before - P_after is positive semi-definite after an update.
  Eigen::SelfAdjointEigenSolver<Cov6> es(before - kf.covariance());
  EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12);
  EXPECT_TRUE(isSymmetricPositiveDefinite(kf.covariance()));
}

TEST(Kalman, GivenNoisyMeasurementsOfAConstantVelocityTargetThenEstimateConverges) {
  KalmanParams params;
  params.position_std = 0.05;
  params.velocity_std = std::sqrt(2.0) * 0.05 / 0.02;  // noise of a difference of two positions
  ConstantVelocityKalman kf(params);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.05);
  const Eigen::Vector3d v(1.2, -0.4, 0.0);
  Eigen::Vector3d prev(0, 0, 0);
  ASSERT_EQ(kf.init(prev, Eigen::Vector3d::Zero()), KalmanStatus::kOk);
  const double dt = 0.02;
  for (int k = 1; k <= 500; ++k) {
    const Eigen::Vector3d truth = v * (k * dt);
    const Eigen::Vector3d z = truth + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    ASSERT_EQ(kf.predict(dt), KalmanStatus::kOk);
    ASSERT_EQ(kf.update(z, (z - prev) / dt), KalmanStatus::kOk);
    prev = z;
    ASSERT_TRUE(isSymmetricPositiveDefinite(kf.covariance())) << k;
  }
  EXPECT_LT((kf.state().tail<3>() - v).norm(), 0.15);
  EXPECT_LT((kf.state().head<3>() - v * 10.0).norm(), 0.1);
}

TEST(Kalman, GivenPositionOnlyUpdateThenPositionVarianceShrinksAndStateMovesTowardMeasurement) {
  ConstantVelocityKalman kf;
  ASSERT_EQ(kf.init(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 0)), KalmanStatus::kOk);
  ASSERT_EQ(kf.predict(0.5), KalmanStatus::kOk);
  const double before = positionTrace(kf.covariance());
  ASSERT_EQ(kf.updatePosition(Eigen::Vector3d(1, 0, 0)), KalmanStatus::kOk);
  EXPECT_LT(positionTrace(kf.covariance()), before);
  EXPECT_GT(kf.state()(0), 0.5);
  EXPECT_GT(kf.state()(3), 0.0);  // velocity pulled along through the cross-covariance
}

TEST(Kalman, GivenBadInputsThenStatusAndFilterUnchanged) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ConstantVelocityKalman kf;
  EXPECT_EQ(kf.predict(0.1), KalmanStatus::kNotInitialised);
  EXPECT_EQ(kf.update(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), KalmanStatus::kNotInitialised);
  EXPECT_EQ(kf.init(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d::Zero()), KalmanStatus::kNonFinite);
  EXPECT_FALSE(kf.initialised());
  Cov6 notPd = Cov6::Identity();
  notPd(2, 2) = -1.0;
  EXPECT_EQ(kf.initState(State6::Zero(), notPd), KalmanStatus::kNotPositiveDefinite);
  Cov6 asym = Cov6::Identity();
  asym(0, 1) = 0.5;
  EXPECT_EQ(kf.initState(State6::Zero(), asym), KalmanStatus::kNotPositiveDefinite);

  ASSERT_EQ(kf.init(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0, 1, 0)), KalmanStatus::kOk);
  const State6 x0 = kf.state();
  const Cov6 P0 = kf.covariance();
  EXPECT_EQ(kf.predict(-0.1), KalmanStatus::kNegativeDt);
  EXPECT_EQ(kf.predict(nan), KalmanStatus::kNonFinite);
  EXPECT_EQ(kf.update(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d::Zero()), KalmanStatus::kNonFinite);
  EXPECT_EQ(kf.updatePosition(Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 0)),
            KalmanStatus::kNonFinite);
  EXPECT_EQ(kf.state(), x0);
  EXPECT_EQ(kf.covariance(), P0);

  State6 xo = State6::Constant(7.0);
  EXPECT_EQ(predict(State6::Zero(), notPd, 1.0, KalmanParams(), &xo, nullptr),
            KalmanStatus::kNotPositiveDefinite);
  EXPECT_EQ(xo, State6::Constant(7.0));

  KalmanParams bad;
  bad.position_std = -1.0;
  EXPECT_EQ(bad.validate(), "position_std");
  ConstantVelocityKalman kb(bad);
  EXPECT_EQ(kb.init(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), KalmanStatus::kBadParams);
  EXPECT_STREQ(toString(KalmanStatus::kNotPositiveDefinite), "not_positive_definite");
}

TEST(Kalman, GivenYamlThenParamsReadOneToOneAndBadValuesNamed) {
  const std::string yaml =
      "accel_psd_xy: 0.9\naccel_psd_z: 0.1\nposition_std: 0.04\nvelocity_std: 0.2\n"
      "initial_velocity_std: 1.5\n";
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<KalmanParams>(yaml, "kf.yaml", &errors);
  ASSERT_TRUE(p.has_value());
  EXPECT_DOUBLE_EQ(p->accel_psd_xy, 0.9);
  EXPECT_DOUBLE_EQ(p->initial_velocity_std, 1.5);
  auto q = ucon::loadParams<KalmanParams>(yaml + "position_sd: 1\n", "kf.yaml", &errors);
  EXPECT_FALSE(q.has_value());
  auto r = ucon::loadParams<KalmanParams>(
      "accel_psd_xy: -1\naccel_psd_z: 0.1\nposition_std: 0.04\nvelocity_std: 0.2\n"
      "initial_velocity_std: 1.5\n", "kf.yaml", &errors);
  EXPECT_FALSE(r.has_value());
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].key, "accel_psd_xy");
}
