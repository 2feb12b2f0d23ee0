// Closed-form checks of the drawing geometry: covariance ellipses, the paper's sectors
// (eqs. 6-7), the colour maps and the scale-bar length.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/plot/geometry.hpp"

using namespace ucon::plot;

TEST(CovarianceEllipse, GivenADiagonalCovarianceThenTheAxesAreNSigmaAlongXAndY) {
  Eigen::Matrix2d c;
  c << 4.0, 0.0, 0.0, 1.0;
  const auto e = covarianceEllipse(c, 2.0);
  ASSERT_TRUE(e);
  EXPECT_NEAR(e->a, 4.0, 1e-12);  // 2 * sqrt(4)
  EXPECT_NEAR(e->b, 2.0, 1e-12);  // 2 * sqrt(1)
  EXPECT_NEAR(std::abs(std::sin(e->angle)), 0.0, 1e-12);
}

TEST(CovarianceEllipse, GivenACorrelatedCovarianceThenTheMajorAxisIsAtFortyFiveDegrees) {
  // Eigenvalues 3 (along (1,1)) and 1 (along (1,-1)).
  Eigen::Matrix2d c;
  c << 2.0, 1.0, 1.0, 2.0;
  const auto e = covarianceEllipse(c, 1.0);
  ASSERT_TRUE(e);
  EXPECT_NEAR(e->a, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(e->b, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(std::cos(e->angle)), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(std::cos(e->angle) * std::sin(e->angle), 0.5, 1e-9);  // (1,1) or (-1,-1)
}

TEST(CovarianceEllipse, GivenNaNOrAnIndefiniteOrAsymmetricMatrixThenNone) {
  Eigen::Matrix2d c;
  c << NAN, 0, 0, 1;
  EXPECT_FALSE(covarianceEllipse(c, 2.0));
  c << 1, 0, 0, -1;
  EXPECT_FALSE(covarianceEllipse(c, 2.0));
  c << 1, 0.5, 0.1, 1;
  EXPECT_FALSE(covarianceEllipse(c, 2.0));
}

TEST(UncertaintySector, GivenAMovingObjectThenRadiusAndAngleFollowEquationsSixAndSeven) {
  SectorParams p;  // h 0.02, k 2, kappa 0.05, s 0.4
  Eigen::Matrix2d S;
  S << 0.01, 0.0, 0.0, 0.04;  // sigma 0.1 along v (x), 0.2 across (y)
  const auto s = uncertaintySector({1, 2}, {1.5, 0.0}, S, true, 0.8, p);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->radius, 1.5 * 0.02 + 2.0 * 0.1 + 0.4 + 0.4, 1e-12);
  EXPECT_NEAR(s->half_angle, std::atan(0.05 * 0.2 / (1.5 * 0.02)), 1e-12);
  EXPECT_NEAR(s->heading, 0.0, 1e-12);
  EXPECT_EQ(s->centre, Eigen::Vector2d(1, 2));
}

TEST(UncertaintySector, GivenTheVelocityAlongYThenTheRolesOfTheVariancesSwap) {
  SectorParams p;
  Eigen::Matrix2d S;
  S << 0.01, 0.0, 0.0, 0.04;
  const auto s = uncertaintySector({0, 0}, {0.0, -2.0}, S, true, 0.0, p);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->radius, 2.0 * 0.02 + 2.0 * 0.2 + 0.4, 1e-12);
  EXPECT_NEAR(s->half_angle, std::atan(0.05 * 0.1 / (2.0 * 0.02)), 1e-12);
  EXPECT_NEAR(s->heading, -M_PI / 2, 1e-12);
}

TEST(UncertaintySector, GivenASlowObjectThenADiskCoveringEveryHeading) {
  SectorParams p;
  Eigen::Matrix2d S;
  S << 0.03, 0.0, 0.0, 0.06;
  const auto s = uncertaintySector({0, 0}, {0.01, 0.0}, S, true, 0.6, p);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->half_angle, M_PI, 1e-12);
  EXPECT_NEAR(s->radius, 0.3 + 0.4 + 2.0 * std::sqrt(0.09), 1e-12);
}

TEST(UncertaintySector, GivenNoCovarianceThenOnlyTheVelocityAndBodyTermsAndZeroAngle) {
  SectorParams p;
  const auto s = uncertaintySector({0, 0}, {1.0, 0.0}, Eigen::Matrix2d::Constant(NAN), false, 0.0, p);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->radius, 0.02 + 0.4, 1e-12);
  EXPECT_NEAR(s->half_angle, 0.0, 1e-12);
  EXPECT_FALSE(uncertaintySector({NAN, 0}, {1, 0}, Eigen::Matrix2d::Zero(), false, 0.0, p));
}

TEST(Colours, GivenTheEndsOfTheSpeedMapThenViridisDarkPurpleAndYellow) {
  const Rgb lo = speedColour(0.0), hi = speedColour(1.0), nan = speedColour(NAN), over = speedColour(7.0);
  EXPECT_LT(lo.g, 0.05);
  EXPECT_GT(lo.b, lo.r);
  EXPECT_GT(hi.r, 0.9);
  EXPECT_GT(hi.g, 0.85);
  EXPECT_LT(hi.b, 0.2);
  EXPECT_EQ(toHex(nan), toHex(lo));
  EXPECT_EQ(toHex(over), toHex(hi));
  EXPECT_EQ(toHex({1, 0, 0.5}), "#ff0080");
  EXPECT_EQ(toHex(idColour(3)), toHex(idColour(13)));
  EXPECT_NE(toHex(idColour(3)), toHex(idColour(4)));
  EXPECT_EQ(toHex(idColour(-1)), toHex(idColour(9)));
}

TEST(NiceLength, GivenAMaximumThenOneTwoOrFiveTimesAPowerOfTenNotAboveIt) {
  EXPECT_DOUBLE_EQ(niceLength(7.3), 5.0);
  EXPECT_DOUBLE_EQ(niceLength(10.0), 10.0);
  EXPECT_DOUBLE_EQ(niceLength(0.9), 0.5);
  EXPECT_DOUBLE_EQ(niceLength(19.0), 10.0);
  EXPECT_DOUBLE_EQ(niceLength(2.5), 2.0);
  EXPECT_DOUBLE_EQ(niceLength(0.0), 0.0);
  EXPECT_DOUBLE_EQ(niceLength(NAN), 0.0);
}

TEST(Bounds, GivenPointsWithNaNThenNaNIsIgnoredAndPaddingGrowsEachSide) {
  Bounds b;
  EXPECT_FALSE(b.valid);
  b.add(1, 2);
  b.add(NAN, 100);
  b.add(3, -2);
  ASSERT_TRUE(b.valid);
  EXPECT_DOUBLE_EQ(b.width(), 2.0);
  EXPECT_DOUBLE_EQ(b.height(), 4.0);
  b.pad(0.1, 0.5);
  EXPECT_DOUBLE_EQ(b.min_x, 0.5);   // max(0.5, 0.2)
  EXPECT_DOUBLE_EQ(b.max_y, 2.5);   // max(0.5, 0.4)
}

TEST(FocusBounds, GivenAFarAwayTrackThenItDoesNotWidenTheViewButNearOnesDo) {
  Bounds robot;
  robot.add(0, 0);
  robot.add(10, 5);
  const Bounds b = focusBounds(robot, {{12, 6}, {-3, 2}, {500, 0}, {NAN, 1}}, 15.0);
  EXPECT_DOUBLE_EQ(b.min_x, -3.0);
  EXPECT_DOUBLE_EQ(b.max_x, 12.0);
  EXPECT_DOUBLE_EQ(b.max_y, 6.0);
  // Without a robot path or map, the objects are the picture.
  const Bounds only = focusBounds(Bounds{}, {{500, 0}, {510, 3}}, 15.0);
  ASSERT_TRUE(only.valid);
  EXPECT_DOUBLE_EQ(only.min_x, 500.0);
  EXPECT_DOUBLE_EQ(only.max_y, 3.0);
}
