// StaticPersistence: a point reaches PERCEPTION_STATIC only once its x-y cell has been occupied
// for the persistence time; movers never hold a cell that long.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "ucon/perception/static_persistence.hpp"

using ucon::perception::StaticPersistence;

namespace {
constexpr int64_t kT0 = 5'000'000;
constexpr int64_t kDt = 20'000;  // 50 Hz
}  // namespace

TEST(StaticPersistence, GivenAFixedPointThenItPassesExactlyOnceItsCellWasOccupiedForThePersistence) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  const std::vector<Eigen::Vector3f> pts{{1.05f, 2.05f, 1.0f}, {1.15f, 2.15f, 0.5f}};  // one cell
  std::vector<char> ok;
  for (int k = 0; k <= 30; ++k) {
    sp.update(kT0 + k * kDt, pts, &ok);
    ASSERT_EQ(ok.size(), 2u);
    const bool expected = k * kDt >= 500'000;  // k >= 25
    EXPECT_EQ(ok[0] != 0, expected) << "frame " << k;
    EXPECT_EQ(ok[1], ok[0]);
  }
}

TEST(StaticPersistence, GivenAPointMovingAtWalkingSpeedThenItNeverPasses) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  std::vector<char> ok;
  for (int k = 0; k < 200; ++k) {
    const float x = 0.5f * static_cast<float>(k) * 0.02f;  // 0.5 m/s: 0.4 s per 0.2 m cell
    sp.update(kT0 + k * kDt, {{x, 0.1f, 1.0f}}, &ok);
    EXPECT_EQ(ok[0], 0) << "frame " << k;
  }
}

TEST(StaticPersistence, GivenACellUnseenForLongerThanTheGapThenItStartsOver) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  const std::vector<Eigen::Vector3f> pt{{-3.0f, -4.0f, 1.0f}};
  std::vector<char> ok;
  int64_t t = kT0;
  for (int k = 0; k < 30; ++k, t += kDt) sp.update(t, pt, &ok);
  EXPECT_EQ(ok[0], 1);
  // A gap shorter than max_gap (0.2 s) keeps the run going...
  t += 200'000;
  sp.update(t, pt, &ok);
  EXPECT_EQ(ok[0], 1);
  // ... a longer one (0.4 s) starts it over.
  t += 400'000;
  sp.update(t, pt, &ok);
  EXPECT_EQ(ok[0], 0);
  for (int k = 0; k < 25; ++k) sp.update(t += kDt, pt, &ok);
  EXPECT_EQ(ok[0], 1);
}

TEST(StaticPersistence, GivenTimeGoingBackwardsOrBadPointsThenItResetsAndNeverCrashes) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  const std::vector<Eigen::Vector3f> pt{{0.0f, 0.0f, 1.0f}};
  std::vector<char> ok;
  for (int k = 0; k < 30; ++k) sp.update(kT0 + k * kDt, pt, &ok);
  EXPECT_EQ(ok[0], 1);
  sp.update(kT0, pt, &ok);  // earlier than the last frame: a new log, start over
  EXPECT_EQ(ok[0], 0);
  const float nan = std::nanf("");
  sp.update(kT0 + kDt, {{nan, 0.0f, 1.0f}, {1e30f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}}, &ok);
  ASSERT_EQ(ok.size(), 3u);
  EXPECT_EQ(ok[0], 0);
  EXPECT_EQ(ok[1], 0);
  sp.update(kT0 + kDt, {}, &ok);
  EXPECT_TRUE(ok.empty());
  EXPECT_THROW(StaticPersistence(0.0, 0.5, 0.3), std::invalid_argument);
  EXPECT_THROW(StaticPersistence(0.2, -1.0, 0.3), std::invalid_argument);
  EXPECT_THROW(StaticPersistence(0.2, 0.5, 0.3, 100), std::invalid_argument);
}

TEST(StaticPersistence, GivenZeroPersistenceThenEveryFinitePointPasses) {
  StaticPersistence sp(0.2, 0.0, 0.3);
  std::vector<char> ok;
  sp.update(kT0, {{1.0f, 1.0f, 1.0f}, {7.0f, -2.0f, 0.4f}}, &ok);
  EXPECT_EQ(ok, (std::vector<char>{1, 1}));
}
