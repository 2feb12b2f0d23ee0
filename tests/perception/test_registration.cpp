// registerTranslation: an object's x-y displacement between two views of its points.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ucon/perception/registration.hpp"

using ucon::perception::Points;
using ucon::perception::registerTranslation;
using ucon::perception::RegistrationParams;

namespace {

// Points on the arc of a circle (centre c, radius r) from bearing a0 to a1, n of them.
Points arc(const Eigen::Vector2d& c, double r, double a0, double a1, int n) {
  Points pts;
  for (int k = 0; k < n; ++k) {
    const double a = a0 + (a1 - a0) * k / (n - 1);
    pts.emplace_back(static_cast<float>(c.x() + r * std::cos(a)), static_cast<float>(c.y() + r * std::sin(a)), 0.8f);
  }
  return pts;
}

Eigen::Vector2d centroid(const Points& p) {
  Eigen::Vector2d s = Eigen::Vector2d::Zero();
  for (const auto& q : p) s += q.head<2>().cast<double>();
  return s / static_cast<double>(p.size());
}

}  // namespace

TEST(Registration, GivenTheSameViewShiftedThenTheShiftIsRecoveredFromAZeroGuess) {
  // The near half of a 0.3 m body seen from the -x side, moved by (0.25, -0.15) (1.5 m/s over 0.2 s).
  const Eigen::Vector2d c(5.0, 1.0), shift(0.25, -0.15);
  const Points before = arc(c, 0.3, M_PI / 2, 3 * M_PI / 2, 30);
  const Points after = arc(c + shift, 0.3, M_PI / 2 + 0.01, 3 * M_PI / 2 + 0.01, 31);  // resampled
  Eigen::Vector2d d;
  ASSERT_TRUE(registerTranslation(before, after, Eigen::Vector2d::Zero(), RegistrationParams{}, &d));
  EXPECT_LT((d - shift).norm(), 0.02) << d.transpose();
}

TEST(Registration, GivenANeighbourMergedIntoTheNewViewThenTheObjectsShiftIsRecoveredWhereTheCentresAreOff) {
  const Eigen::Vector2d c(5.0, 1.0), shift(0.2, 0.1);
  const Points before = arc(c, 0.3, M_PI / 2, 3 * M_PI / 2, 30);
  Points after = arc(c + shift, 0.3, M_PI / 2, 3 * M_PI / 2, 30);
  // Someone else's near side, 0.5 m beside it, joins the cluster.
  const Points other = arc(c + shift + Eigen::Vector2d(0.1, 0.75), 0.25, M_PI / 2, 3 * M_PI / 2, 20);
  after.insert(after.end(), other.begin(), other.end());
  const Eigen::Vector2d naive = centroid(after) - centroid(before);
  ASSERT_GT((naive - shift).norm(), 0.2) << "the test needs a merge that moves the centroid";
  Eigen::Vector2d d;
  ASSERT_TRUE(registerTranslation(before, after, shift * 0.5, RegistrationParams{}, &d));
  EXPECT_LT((d - shift).norm(), 0.03) << d.transpose();
}

TEST(Registration, GivenPartOfTheNewViewHiddenThenTheShiftIsRecoveredWhereTheCentresAreOff) {
  const Eigen::Vector2d c(5.0, 1.0), shift(-0.1, 0.2);
  const Points before = arc(c, 0.4, M_PI / 2, 3 * M_PI / 2, 40);
  const Points after = arc(c + shift, 0.4, M_PI / 2, M_PI + 0.2, 22);  // the lower third hidden
  const Eigen::Vector2d naive = centroid(after) - centroid(before);
  ASSERT_GT((naive - shift).norm(), 0.1);
  Eigen::Vector2d d;
  RegistrationParams p;
  p.min_inliers = 0.4;  // half the old view has no counterpart now
  ASSERT_TRUE(registerTranslation(before, after, Eigen::Vector2d::Zero(), p, &d));
  EXPECT_LT((d - shift).norm(), 0.03) << d.transpose();
}

TEST(Registration, GivenTooLittleToAlignThenItRefusesAndLeavesTheResultAlone) {
  const Eigen::Vector2d c(5.0, 1.0);
  const Points view = arc(c, 0.3, M_PI / 2, 3 * M_PI / 2, 30);
  const Points few = arc(c, 0.3, M_PI / 2, M_PI, 4);
  Eigen::Vector2d d(7.0, 7.0);
  EXPECT_FALSE(registerTranslation(few, view, Eigen::Vector2d::Zero(), RegistrationParams{}, &d));
  EXPECT_FALSE(registerTranslation(view, few, Eigen::Vector2d::Zero(), RegistrationParams{}, &d));
  EXPECT_FALSE(registerTranslation(view, Points{}, Eigen::Vector2d::Zero(), RegistrationParams{}, &d));
  // Nothing within the first gate of the guess.
  const Points far = arc(c + Eigen::Vector2d(3.0, 0.0), 0.3, M_PI / 2, 3 * M_PI / 2, 30);
  EXPECT_FALSE(registerTranslation(view, far, Eigen::Vector2d::Zero(), RegistrationParams{}, &d));
  EXPECT_FALSE(registerTranslation(view, view, Eigen::Vector2d(NAN, 0.0), RegistrationParams{}, &d));
  EXPECT_EQ(d, Eigen::Vector2d(7.0, 7.0));
  // A non-finite point pairs with nothing; the others still align.
  Points bad = view;
  bad[3].x() = std::numeric_limits<float>::quiet_NaN();
  Eigen::Vector2d e;
  ASSERT_TRUE(registerTranslation(bad, view, Eigen::Vector2d::Zero(), RegistrationParams{}, &e));
  EXPECT_LT(e.norm(), 1e-6);
  ASSERT_TRUE(registerTranslation(view, bad, Eigen::Vector2d::Zero(), RegistrationParams{}, &e));
  EXPECT_LT(e.norm(), 0.01);  // the point without its counterpart pairs with a neighbour
}
