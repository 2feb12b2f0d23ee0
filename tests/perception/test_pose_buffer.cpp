// Pose interpolation at a frame's time.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/pose_buffer.hpp"

using ucon::perception::PoseBuffer;

namespace {
ucon::robot_pose_t pose(int64_t t, double x, double yaw) {
  ucon::robot_pose_t p{};
  p.utime = t;
  p.valid = true;
  p.x = x;
  p.qw = std::cos(yaw / 2);
  p.qz = std::sin(yaw / 2);
  return p;
}
}  // namespace

TEST(PoseBuffer, GivenTwoPosesThenTheMidpointIsInterpolatedInPositionAndHeading) {
  PoseBuffer b;
  ASSERT_EQ(b.add(pose(1000, 0.0, 0.0)), PoseBuffer::AddResult::kAdded);
  ASSERT_EQ(b.add(pose(3000, 2.0, M_PI / 2)), PoseBuffer::AddResult::kAdded);
  const auto T = b.at(2000, 0.1);
  ASSERT_TRUE(T);
  EXPECT_NEAR(T->translation().x(), 1.0, 1e-12);
  const Eigen::Vector3d ex = T->linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(ex.y(), ex.x()), M_PI / 4, 1e-9);
}

TEST(PoseBuffer, GivenTimesOutsideTheSpanThenTheNearestPoseIsUsedOnlyWithinTheGap) {
  PoseBuffer b;
  EXPECT_FALSE(b.at(1000, 1.0));
  b.add(pose(1'000'000, 1.0, 0.0));
  EXPECT_TRUE(b.at(1'050'000, 0.1));
  EXPECT_FALSE(b.at(1'200'000, 0.1));
  EXPECT_FALSE(b.at(800'000, 0.1));
  EXPECT_EQ(b.add(pose(1'000'000, 1.0, 0.0)), PoseBuffer::AddResult::kOutOfOrder);
  auto q = pose(2'000'000, 1.0, 0.0);
  q.qw = q.qx = q.qy = q.qz = 0.0;
  EXPECT_EQ(b.add(q), PoseBuffer::AddResult::kNonFinite);
}
