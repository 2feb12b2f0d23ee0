#include <gtest/gtest.h>

#include <cmath>

#include "ucon/trajectory/quintic_hermite.hpp"

using namespace ucon::trajectory;

TEST(QuinticHermite, GivenEndStatesThenPolynomialMatchesThemAtBothEnds) {
  const double T = 1.7;
  const auto c = quinticHermiteCoefficients(0.3, -1.0, 2.0, 4.0, 0.5, -3.0, T);
  double p = 0, v = 0, a = 0;
  for (int j = 0; j < 6; ++j) {
    p += c[j] * std::pow(T, j);
    if (j >= 1) v += j * c[j] * std::pow(T, j - 1);
    if (j >= 2) a += j * (j - 1) * c[j] * std::pow(T, j - 2);
  }
  EXPECT_NEAR(c[0], 0.3, 1e-15);
  EXPECT_NEAR(c[1], -1.0, 1e-15);
  EXPECT_NEAR(c[2], 1.0, 1e-15);
  EXPECT_NEAR(p, 4.0, 1e-12);
  EXPECT_NEAR(v, 0.5, 1e-12);
  EXPECT_NEAR(a, -3.0, 1e-12);
}

TEST(QuinticHermite, GivenKnotsOfAQuinticThenReproducedExactly) {
  // x(t) = t^5 - 2 t^2 + 1 is itself a quintic: Hermite interpolation reproduces it.
  auto x = [](double t) { return std::pow(t, 5) - 2 * t * t + 1; };
  auto dx = [](double t) { return 5 * std::pow(t, 4) - 4 * t; };
  auto ddx = [](double t) { return 20 * std::pow(t, 3) - 4; };
  std::vector<KnotState> knots;
  for (double t : {0.0, 0.4, 1.0, 1.5}) {
    KnotState k;
    k.t = t;
    k.position = {x(t), 2 * t, 0};
    k.velocity = {dx(t), 2, 0};
    k.acceleration = {ddx(t), 0, 0};
    knots.push_back(k);
  }
  PiecewisePolynomial p;
  ASSERT_EQ(buildQuinticHermite(1'000'000, knots, 2, &p), TrajectoryStatus::kOk);
  EXPECT_EQ(p.order1(), 6);
  EXPECT_EQ(p.numPieces(), 3);
  for (double t = 0.0; t <= 1.5; t += 0.05) {
    const TrajectorySample s = p.sampleRelative(t);
    EXPECT_NEAR(s.position.x(), x(t), 1e-9) << t;
    EXPECT_NEAR(s.velocity.x(), dx(t), 1e-9) << t;
    EXPECT_NEAR(s.jerk.x(), 60 * t * t, 1e-7) << t;
    EXPECT_NEAR(s.position.y(), 2 * t, 1e-12) << t;
  }
}

TEST(QuinticHermite, GivenNonIncreasingKnotTimesThenRejected) {
  std::vector<KnotState> knots(3);
  knots[0].t = 0.0;
  knots[1].t = 1.0;
  knots[2].t = 1.0;
  PiecewisePolynomial p;
  EXPECT_EQ(buildQuinticHermite(1'000'000, knots, 2, &p), TrajectoryStatus::kBadDuration);
  EXPECT_EQ(buildQuinticHermite(1'000'000, {knots[0]}, 2, &p), TrajectoryStatus::kNoPieces);
  EXPECT_FALSE(p.valid());
}
