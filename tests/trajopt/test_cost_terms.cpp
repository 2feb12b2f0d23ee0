// The static-clearance and limit penalties and the horizon taper of the dynamic cost: values
// against closed forms, gradients against finite differences.
#include <gtest/gtest.h>

#include <cmath>

#include "test_fixtures.hpp"
#include "ucon/trajopt/cost_terms.hpp"

using namespace ucon::trajopt;
using trajopt_test::DiscField;
using trajopt_test::finiteDifference;
using trajopt_test::relativeError;

TEST(CostTerms, GivenStaticAndLimitPenaltiesThenValuesAndGradientsMatch) {
  const DiscField field({{Eigen::Vector2d(0, 0), 1.0}});
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  const Eigen::Vector2d p(1.2, 0.1);
  const double xi = std::hypot(1.2, 0.1) - 1.0;
  EXPECT_NEAR(staticClearanceCost(field, p, 0.5, 10.0, &g), 10.0 * std::pow(0.5 - xi, 3), 1e-12);
  auto fs = [&](const Eigen::VectorXd& y) {
    Eigen::Vector2d gg = Eigen::Vector2d::Zero();
    return staticClearanceCost(field, y, 0.5, 10.0, &gg);
  };
  EXPECT_LT(relativeError(g, finiteDifference(fs, p, 1e-6)), 1e-6);
  g.setZero();
  EXPECT_EQ(staticClearanceCost(field, Eigen::Vector2d(3, 0), 0.5, 10.0, &g), 0.0);
  EXPECT_TRUE(g.isZero());

  const Eigen::Vector2d v(1.3, 0.9);
  g.setZero();
  EXPECT_NEAR(limitCost(v, 1.5, 100.0, &g), 100.0 * std::pow(1.3 * 1.3 + 0.81 - 2.25, 3), 1e-12);
  auto fl = [&](const Eigen::VectorXd& y) {
    Eigen::Vector2d gg = Eigen::Vector2d::Zero();
    return limitCost(y, 1.5, 100.0, &gg);
  };
  EXPECT_LT(relativeError(g, finiteDifference(fl, v, 1e-7)), 1e-6);
  g.setZero();
  EXPECT_EQ(limitCost(Eigen::Vector2d(1.0, 0.5), 1.5, 100.0, &g), 0.0);
}

TEST(CostTerms, GivenTheHorizonTaperThenItIsSmoothAndItsDerivativeMatches) {
  double dw;
  EXPECT_EQ(horizonWeight(1.0, 3.0, &dw), 1.0);
  EXPECT_EQ(horizonWeight(3.5, 3.0, &dw), 0.0);
  for (double t : {2.55, 2.75, 2.95}) {
    horizonWeight(t, 3.0, &dw);
    double d0;
    const double fd = (horizonWeight(t + 1e-7, 3.0, &d0) - horizonWeight(t - 1e-7, 3.0, &d0)) / 2e-7;
    EXPECT_NEAR(dw, fd, 1e-6);
  }
}
