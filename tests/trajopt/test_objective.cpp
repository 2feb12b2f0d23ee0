#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "test_fixtures.hpp"
#include "ucon/minco/time_map.hpp"
#include "ucon/trajopt/objective.hpp"

using namespace ucon::trajopt;
using trajopt_test::DiscField;
using trajopt_test::finiteDifference;
using trajopt_test::relativeError;

namespace {

constexpr int64_t kStart = 5'000'000;

PredictedObstacle crossing(int64_t id, Eigen::Vector2d p, Eigen::Vector2d v, double radius) {
  PredictedObstacle o;
  o.id = id;
  o.utime = kStart - 40'000;
  o.state << p.x(), p.y(), 0.0, v.x(), v.y(), 0.0;
  ucon::kalman::Cov6 P = ucon::kalman::Cov6::Zero();
  P.diagonal() << 0.01, 0.012, 0.01, 0.15, 0.12, 0.05;
  P(0, 3) = P(3, 0) = 0.01;
  P(1, 4) = P(4, 1) = 0.008;
  o.covariance = P;
  o.radius = radius;
  return o;
}

struct Scenario {
  DiscField field{{{Eigen::Vector2d(3.0, 0.9), 0.5}, {Eigen::Vector2d(6.0, -0.6), 0.4}}};
  PlanRequest request;
  Scenario() {
    request.start_utime = kStart;
    request.start << 0.0, 0.8, 0.1, 0.0, 0.1, -0.2;
    request.goal << 9.0, 0.0, 0.0, 1.0, 0.0, 0.0;
    request.inner_waypoints = {Eigen::Vector2d(2.2, 0.3), Eigen::Vector2d(4.5, 0.2), Eigen::Vector2d(6.8, 0.6)};
    request.durations = {1.6, 1.4, 1.5, 1.3};
    request.field = &field;
    // Crossing the path ahead, one slow (disk), one head-on.
    request.obstacles = {crossing(1, {2.6, -1.2}, {0.2, 1.0}, 0.3), crossing(2, {4.2, 0.5}, {0.01, 0.0}, 0.25),
                         crossing(3, {7.5, 0.4}, {-1.0, 0.0}, 0.3), crossing(4, {40, 40}, {0, 0}, 0.3)};
  }
};

OptimizerParams baseParams() {
  OptimizerParams p;
  p.weight_static = 0.0;
  p.weight_velocity = 0.0;
  p.weight_acceleration = 0.0;
  p.lambda_d = 0.0;
  p.dynamic_horizon = 4.0;
  return p;
}

struct Eval {
  double f;
  Eigen::VectorXd g;
  CostBreakdown b;
};

Eval evalAt(SectorMincoObjective& obj, const Eigen::VectorXd& x) {
  Eval e;
  e.g.resize(x.size());
  e.f = obj.evaluate(x.data(), e.g.data());
  e.b = obj.breakdown();
  return e;
}

// Gradient of (J_with - J_base) against finite differences of the same difference: isolates
// one cost term's gradient (energy and time are in both).
void expectTermGradient(const OptimizerParams& with, const char* name, double CostBreakdown::*term) {
  Scenario sc;
  SectorMincoObjective a(with, ucon::kalman::KalmanParams()), b(baseParams(), ucon::kalman::KalmanParams());
  ASSERT_EQ(a.setup(sc.request), "");
  ASSERT_EQ(b.setup(sc.request), "");
  const Eigen::VectorXd x = a.initialGuess();
  const Eval ea = evalAt(a, x), eb = evalAt(b, x);
  ASSERT_GT(ea.b.*term, 1e-3) << name << " must be active in the test scenario";
  auto diff = [&](const Eigen::VectorXd& y) {
    return a.evaluate(y.data(), nullptr) - b.evaluate(y.data(), nullptr);
  };
  const Eigen::VectorXd fd = finiteDifference(diff, x, 1e-6);
  const Eigen::VectorXd an = ea.g - eb.g;
  EXPECT_LT(relativeError(an, fd), 1e-5) << name << "\nanalytic " << an.transpose() << "\nfd       " << fd.transpose();
}

}  // namespace

TEST(Objective, GivenEnergyAndTimeOnlyThenGradientWrtWaypointsAndDurationsMatchesFiniteDifferences) {
  Scenario sc;
  SectorMincoObjective obj(baseParams(), ucon::kalman::KalmanParams());
  ASSERT_EQ(obj.setup(sc.request), "");
  const Eigen::VectorXd x = obj.initialGuess();
  ASSERT_EQ(x.size(), 2 * 3 + 4);
  const Eval e = evalAt(obj, x);
  EXPECT_NEAR(e.b.time, 10.0 * (1.6 + 1.4 + 1.5 + 1.3), 1e-9);  // the guess' durations round-trip τ
  EXPECT_EQ(e.b.dynamic, 0.0);
  auto f = [&](const Eigen::VectorXd& y) { return obj.evaluate(y.data(), nullptr); };
  EXPECT_LT(relativeError(e.g, finiteDifference(f, x, 1e-6)), 1e-6);
}

TEST(Objective, GivenEachPenaltyTermAloneThenItsGradientMatchesFiniteDifferences) {
  OptimizerParams p = baseParams();
  p.weight_static = 1e4;
  expectTermGradient(p, "static", &CostBreakdown::static_clearance);
  p = baseParams();
  p.weight_velocity = 1e3;
  p.max_velocity = 1.0;
  expectTermGradient(p, "velocity", &CostBreakdown::velocity);
  p = baseParams();
  p.weight_acceleration = 1e3;
  p.max_acceleration = 0.3;
  expectTermGradient(p, "acceleration", &CostBreakdown::acceleration);
  for (ObstacleModel m : {ObstacleModel::kSector, ObstacleModel::kNoUncertainty, ObstacleModel::kFapp}) {
    p = baseParams();
    p.lambda_d = 5e3;
    p.obstacle_model = m;
    expectTermGradient(p, toString(m), &CostBreakdown::dynamic);
  }
}

TEST(Objective, GivenTheWholeObjectiveThenGradientMatchesFiniteDifferencesAtSeveralPoints) {
  Scenario sc;
  OptimizerParams p;  // paper weights
  p.max_velocity = 1.2;
  p.max_acceleration = 0.8;
  p.dynamic_horizon = 4.0;
  SectorMincoObjective obj(p, ucon::kalman::KalmanParams());
  ASSERT_EQ(obj.setup(sc.request), "");
  EXPECT_EQ(obj.tracks().size(), 3u);  // the far obstacle is culled
  Eigen::VectorXd x = obj.initialGuess();
  for (int k = 0; k < 3; ++k) {
    const Eval e = evalAt(obj, x);
    EXPECT_GT(e.b.dynamic, 0.0);
    EXPECT_GT(e.b.static_clearance, 0.0);
    auto f = [&](const Eigen::VectorXd& y) { return obj.evaluate(y.data(), nullptr); };
    const Eigen::VectorXd fd = finiteDifference(f, x, 1e-6);
    EXPECT_LT(relativeError(e.g, fd), 1e-5) << "point " << k << "\nanalytic " << e.g.transpose() << "\nfd " << fd.transpose();
    EXPECT_NEAR(e.f, e.b.total(), 1e-9 * std::abs(e.f));
    // Move to a different point: shift waypoints, change times (τ on both sides of 0).
    x.head(6) += Eigen::VectorXd::LinSpaced(6, -0.2, 0.25);
    x.tail(4) += Eigen::VectorXd::LinSpaced(4, -0.4, 0.3);
  }
}

TEST(Objective, GivenTheSameInputTwiceThenIdenticalValueAndGradient) {
  Scenario sc;
  SectorMincoObjective a{OptimizerParams{}, ucon::kalman::KalmanParams{}}, b{OptimizerParams{}, ucon::kalman::KalmanParams{}};
  ASSERT_EQ(a.setup(sc.request), "");
  ASSERT_EQ(b.setup(sc.request), "");
  const Eigen::VectorXd x = a.initialGuess();
  const Eval ea = evalAt(a, x), eb = evalAt(b, x);
  const Eval ea2 = evalAt(a, x);
  EXPECT_EQ(ea.f, eb.f);
  EXPECT_EQ(ea.f, ea2.f);
  EXPECT_TRUE(ea.g == eb.g);
}

TEST(Objective, GivenBadRequestsThenSetupNamesTheProblem) {
  Scenario sc;
  SectorMincoObjective obj{OptimizerParams{}, ucon::kalman::KalmanParams{}};
  PlanRequest r = sc.request;
  r.durations[1] = -1.0;
  EXPECT_NE(obj.setup(r), "");
  r = sc.request;
  r.inner_waypoints.pop_back();
  EXPECT_NE(obj.setup(r), "");
  r = sc.request;
  r.goal(0, 0) = std::nan("");
  EXPECT_NE(obj.setup(r), "");
  r = sc.request;
  r.start_utime = 0;
  EXPECT_NE(obj.setup(r), "");
  r = sc.request;
  r.obstacles[0].state(3) = std::nan("");
  r.obstacles[1].covariance(1, 1) = -3.0;
  EXPECT_EQ(obj.setup(r), "");
  EXPECT_EQ(obj.obstaclesRejected(), 1);
  EXPECT_EQ(obj.obstaclesWithoutCovariance(), 1);
}
