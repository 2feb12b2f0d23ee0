// The uncertainty sector (eqs. 6-7) and the dynamic-obstacle cost J_d (eqs. 8-10): its shape
// over the horizon, and dJ/dp, dJ/dt against finite differences for every obstacle model.
#include <gtest/gtest.h>

#include <cmath>

#include "test_fixtures.hpp"
#include "ucon/trajopt/uncertainty_sector.hpp"

using namespace ucon::trajopt;
using trajopt_test::finiteDifference;
using trajopt_test::relativeError;

namespace {

PredictedObstacle movingObstacle(double vx, double vy) {
  PredictedObstacle o;
  o.id = 7;
  o.utime = 1'000'000;  // 0.1 s before the plan start below
  o.state << 2.0, 1.0, 0.5, vx, vy, 0.0;
  ucon::kalman::Cov6 P = ucon::kalman::Cov6::Zero();
  P.diagonal() << 0.02, 0.03, 0.01, 0.2, 0.1, 0.05;
  P(0, 1) = P(1, 0) = 0.005;
  P(0, 3) = P(3, 0) = 0.01;
  P(1, 4) = P(4, 1) = -0.008;
  o.covariance = P;
  o.radius = 0.35;
  return o;
}

constexpr int64_t kPlanStart = 1'100'000;

ObstacleTrack prepare(const PredictedObstacle& o, const OptimizerParams& params) {
  ObstacleTrack tr;
  bool cov_ok = false;
  EXPECT_TRUE(prepareObstacle(o, kPlanStart, ucon::kalman::KalmanParams(), params, &tr, &cov_ok));
  return tr;
}

// Checks dJ/dp and dJ/dt of the dynamic cost at (p, t) against central differences.
void expectDynamicGradient(const ObstacleTrack& tr, const OptimizerParams& params, const Eigen::Vector2d& p,
                           double t, double min_value) {
  Eigen::Vector2d gp = Eigen::Vector2d::Zero();
  double gt = 0.0;
  const double J = dynamicObstacleCost(tr, params, p, t, &gp, &gt);
  ASSERT_GT(J, min_value) << "test point must be where the cost is active";
  Eigen::Vector3d x(p.x(), p.y(), t);
  auto f = [&](const Eigen::VectorXd& y) {
    Eigen::Vector2d g2 = Eigen::Vector2d::Zero();
    double g1 = 0.0;
    return dynamicObstacleCost(tr, params, y.head<2>(), y(2), &g2, &g1);
  };
  const Eigen::VectorXd fd = finiteDifference(f, x, 1e-6);
  Eigen::VectorXd an(3);
  an << gp, gt;
  EXPECT_LT(relativeError(an, fd), 1e-5) << "analytic " << an.transpose() << " fd " << fd.transpose();
}

}  // namespace

TEST(UncertaintySector, GivenASectorObstacleThenGradientsWrtPositionAndTimeMatchFiniteDifferences) {
  OptimizerParams params;
  const ObstacleTrack tr = prepare(movingObstacle(1.0, 0.3), params);
  ASSERT_TRUE(tr.use_covariance);
  for (double t : {0.0, 0.4, 1.3}) {
    const SectorShape s = sectorAt(tr, t, params);
    const Eigen::Vector2d dir = tr.dir, perp = tr.perp;
    // Inside the cone near the rim, at the lateral edge, behind (body only), near the body edge.
    expectDynamicGradient(tr, params, s.centre + 0.9 * s.radius * dir + 0.05 * perp, t, 1e-4);
    expectDynamicGradient(tr, params, s.centre + 0.6 * s.radius * (std::cos(s.half_angle) * dir + std::sin(s.half_angle) * perp), t, 1e-4);
    expectDynamicGradient(tr, params, s.centre - 0.9 * s.body_radius * dir + 0.1 * perp, t, 1e-3);
    expectDynamicGradient(tr, params, s.centre + 1.0 * s.body_radius * perp, t, 1e-3);
  }
}

TEST(UncertaintySector, GivenAblationFappAndSlowObstaclesThenGradientsMatchFiniteDifferences) {
  OptimizerParams params;
  params.obstacle_model = ObstacleModel::kNoUncertainty;
  ObstacleTrack tr = prepare(movingObstacle(1.0, 0.3), params);
  EXPECT_FALSE(tr.use_covariance);
  expectDynamicGradient(tr, params, sectorAt(tr, 0.5, params).centre + Eigen::Vector2d(0.5, 0.3), 0.5, 1e-4);
  params.obstacle_model = ObstacleModel::kFapp;
  tr = prepare(movingObstacle(1.0, 0.3), params);
  expectDynamicGradient(tr, params, sectorAt(tr, 0.5, params).centre + Eigen::Vector2d(0.8, 0.3), 0.5, 1e-4);
  params.obstacle_model = ObstacleModel::kSector;
  tr = prepare(movingObstacle(0.01, 0.0), params);
  EXPECT_TRUE(tr.disk);
  const SectorShape s = sectorAt(tr, 0.8, params);
  expectDynamicGradient(tr, params, s.centre + Eigen::Vector2d(-0.7, 0.9) * s.radius / std::hypot(0.7, 0.9), 0.8, 1e-3);
}

TEST(UncertaintySector, GivenAMovingObstacleThenCostIsHighInsideTheSectorAndLowBesideIt) {
  OptimizerParams params;
  const ObstacleTrack tr = prepare(movingObstacle(1.2, 0.0), params);
  const double t = 1.0;
  const SectorShape s = sectorAt(tr, t, params);
  EXPECT_GT(s.radius, s.body_radius + 0.1);  // uncertainty stretches it along the motion
  Eigen::Vector2d g;
  double gt;
  auto J = [&](const Eigen::Vector2d& p) { g.setZero(); gt = 0; return dynamicObstacleCost(tr, params, p, t, &g, &gt); };
  const Eigen::Vector2d ahead = s.centre + (s.body_radius + 0.5 * (s.radius - s.body_radius)) * tr.dir;
  const Eigen::Vector2d beside = s.centre + (s.body_radius + 0.5 * (s.radius - s.body_radius)) * tr.perp;
  const Eigen::Vector2d behind = s.centre - (s.body_radius + 0.5 * (s.radius - s.body_radius)) * tr.dir;
  EXPECT_GT(J(ahead), 0.5);      // inside the sector: the intended meaning (REFERENCE §5)
  EXPECT_LT(J(beside), 0.05);    // the lateral region is released
  EXPECT_LT(J(behind), 0.05);
  EXPECT_GT(J(s.centre - 0.5 * s.body_radius * tr.dir), 0.9);  // the body is costly in every direction
  EXPECT_GT(J(s.centre + 0.5 * s.body_radius * tr.perp), 0.9);
  EXPECT_EQ(J(s.centre + Eigen::Vector2d(20, 0)), 0.0);        // beyond the cutoff: exactly 0
}

TEST(UncertaintySector, GivenCovarianceThenSectorGrowsAlongTheHorizonAndNotWithoutIt) {
  OptimizerParams params;
  const ObstacleTrack tr = prepare(movingObstacle(1.0, 0.0), params);
  const SectorShape a = sectorAt(tr, 0.2, params), b = sectorAt(tr, 2.0, params);
  EXPECT_GT(b.radius, a.radius + 0.1);
  EXPECT_GT(b.half_angle, a.half_angle);
  EXPECT_NEAR((b.centre - a.centre).x(), 1.8, 1e-12);  // constant-velocity mean
  // Closed form of R at t: |v| h + k sqrt(Σ_xx(t)) + r + s with Σ from common/kalman.
  ucon::kalman::State6 xn;
  ucon::kalman::Cov6 Pn;
  const auto o = movingObstacle(1.0, 0.0);
  ASSERT_EQ(ucon::kalman::predict(o.state, o.covariance, 2.1, ucon::kalman::KalmanParams(), &xn, &Pn),
            ucon::kalman::KalmanStatus::kOk);
  EXPECT_NEAR(b.radius, 1.0 * 0.02 + 2.0 * std::sqrt(Pn(0, 0)) + 0.35 + params.safe_distance, 1e-12);
  EXPECT_NEAR(b.half_angle, std::atan(0.05 * std::sqrt(Pn(1, 1)) / (1.0 * 0.02)), 1e-12);
  params.obstacle_model = ObstacleModel::kNoUncertainty;
  const ObstacleTrack tn = prepare(movingObstacle(1.0, 0.0), params);
  EXPECT_NEAR(sectorAt(tn, 2.0, params).radius, sectorAt(tn, 0.2, params).radius, 1e-15);
  EXPECT_NEAR(sectorAt(tn, 2.0, params).half_angle, 0.0, 1e-15);
}

TEST(UncertaintySector, GivenBadObstaclesThenRejectedOrUsedWithoutCovariance) {
  OptimizerParams params;
  ObstacleTrack tr;
  bool cov_ok = true;
  PredictedObstacle o = movingObstacle(1, 0);
  o.state(0) = std::nan("");
  EXPECT_FALSE(prepareObstacle(o, kPlanStart, ucon::kalman::KalmanParams(), params, &tr, &cov_ok));
  o = movingObstacle(1, 0);
  o.covariance(0, 0) = -1.0;
  ASSERT_TRUE(prepareObstacle(o, kPlanStart, ucon::kalman::KalmanParams(), params, &tr, &cov_ok));
  EXPECT_FALSE(cov_ok);
  EXPECT_FALSE(tr.use_covariance);
  o.covariance(0, 0) = std::nan("");
  ASSERT_TRUE(prepareObstacle(o, kPlanStart, ucon::kalman::KalmanParams(), params, &tr, &cov_ok));
  EXPECT_FALSE(cov_ok);
  // Still avoided: the body and the no-uncertainty sector remain.
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  double gt = 0.0;
  EXPECT_GT(dynamicObstacleCost(tr, params, sectorAt(tr, 0.0, params).centre, 0.0, &g, &gt), 0.99);
}
