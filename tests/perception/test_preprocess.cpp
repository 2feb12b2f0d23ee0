// Pre-processing: every LiDAR point placed in the world with the robot's pose at its own time.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/pose_buffer.hpp"
#include "ucon/perception/preprocess.hpp"

using namespace ucon::perception;

namespace {

// The robot drives at 1 m/s along x (an omnidirectional base) while turning at 1 rad/s.
constexpr double kSpeed = 1.0, kYawRate = 1.0;
constexpr int64_t kT0 = 10'000'000;  // [us]

ucon::robot_pose_t truePose(int64_t utime) {
  const double t = 1e-6 * static_cast<double>(utime - kT0);
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = true;
  p.x = kSpeed * t;
  p.yaw = kYawRate * t;
  p.qw = std::cos(p.yaw / 2);
  p.qz = std::sin(p.yaw / 2);
  p.vx = kSpeed;
  p.wz = kYawRate;
  return p;
}

// A 20 ms frame from kT0 of a wall of points 5 m ahead, point i measured at i * 20 ms / n,
// in the base frame of the robot at that instant. `world` gets where each point really is.
ucon::point_cloud_t wallFrame(std::vector<Eigen::Vector3f>* world) {
  const int n = 200;
  ucon::point_cloud_t c{};
  c.utime = kT0;
  c.frame_id = "base";
  c.duration_us = 20'000;
  c.num_points = n;
  for (int i = 0; i < n; ++i) {
    const int64_t off_us = static_cast<int64_t>(i) * 20'000 / n;
    const Eigen::Vector3d w(5.0, -2.0 + 4.0 * i / n, 1.0);
    const auto p = truePose(kT0 + off_us);
    const double cy = std::cos(p.yaw), sy = std::sin(p.yaw);
    const double dx = w.x() - p.x, dy = w.y() - p.y;
    c.x.push_back(static_cast<float>(cy * dx + sy * dy));
    c.y.push_back(static_cast<float>(-sy * dx + cy * dy));
    c.z.push_back(static_cast<float>(w.z()));
    c.t_offset_ns.push_back(static_cast<int32_t>(off_us * 1000));
    world->push_back(w.cast<float>());
  }
  return c;
}

double worstError(const Frame& f, const std::vector<Eigen::Vector3f>& world) {
  double worst = 0.0;
  for (std::size_t i = 0; i < world.size(); ++i) worst = std::max(worst, double((f.returns[i] - world[i]).norm()));
  return worst;
}

}  // namespace

TEST(PoseBuffer, GivenATimePastTheNewestPoseThenItIsExtrapolatedWithThatPosesVelocityWithinTheGap) {
  PoseBuffer b;
  ASSERT_EQ(b.add(truePose(kT0)), PoseBuffer::AddResult::kAdded);
  const auto T = b.at(kT0 + 50'000, 0.1);
  ASSERT_TRUE(T);
  EXPECT_NEAR(T->translation().x(), 0.05, 1e-12);
  const Eigen::Vector3d ex = T->linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(ex.y(), ex.x()), 0.05, 1e-9);
  EXPECT_FALSE(b.at(kT0 + 150'000, 0.1));
}

TEST(Preprocessor, GivenADrivingAndTurningSensorThenEachPointIsPlacedWithThePoseAtItsOwnTime) {
  const PerceptionParams params;
  const AngularGrid fine(1.0), coarse(3.0);
  Preprocessor pre(params.preprocess, fine, coarse);
  PoseBuffer poses;
  for (int64_t t = kT0 - 20'000; t <= kT0 + 20'000; t += 10'000) poses.add(truePose(t));
  std::vector<Eigen::Vector3f> world;
  const auto cloud = wallFrame(&world);
  Frame f;
  const auto r = pre.process(cloud, *poses.at(kT0, 0.1), poses, 0.1, &f);
  ASSERT_EQ(f.returns.size(), world.size());
  EXPECT_FALSE(r.pose_extrapolated);
  // The nearest 0.2 ms pose sample: at most 0.1 ms * (1 m/s + 1 rad/s * 5.4 m) off.
  EXPECT_LT(worstError(f, world), 2e-3);

  // One pose for the whole frame (the placement without time offsets) is centimetres off.
  Preprocessor one(params.preprocess, fine, coarse);
  auto untimed = cloud;
  untimed.t_offset_ns.assign(untimed.t_offset_ns.size(), 0);
  Frame g;
  one.process(untimed, *poses.at(kT0, 0.1), poses, 0.1, &g);
  EXPECT_GT(worstError(g, world), 0.08);
}

TEST(Preprocessor, GivenAFrameEndingAfterTheNewestPoseThenItsLastPointsAreExtrapolatedAndCounted) {
  const PerceptionParams params;
  const AngularGrid fine(1.0), coarse(3.0);
  Preprocessor pre(params.preprocess, fine, coarse);
  PoseBuffer poses;
  for (int64_t t = kT0 - 20'000; t <= kT0 + 5'000; t += 5'000) poses.add(truePose(t));  // the last 15 ms missing
  std::vector<Eigen::Vector3f> world;
  const auto cloud = wallFrame(&world);
  Frame f;
  const auto r = pre.process(cloud, *poses.at(kT0, 0.1), poses, 0.1, &f);
  EXPECT_TRUE(r.pose_extrapolated);
  EXPECT_LT(worstError(f, world), 2e-3);
}

TEST(Preprocessor, GivenAnOdometryFrameThatDriftedInHeightThenGroundIsCutAtTheFloorUnderTheRobot) {
  // An odometry's frame drifts in z by centimetres over tens of metres: the floor under the
  // robot is at the base's z, not at world z 0. Floor points (base z 0) are ground and a box
  // (base z 0.3-1.0 m) is kept, whether the frame drifted up or down.
  const PerceptionParams params;
  const AngularGrid fine(1.0), coarse(3.0);
  ucon::point_cloud_t c{};
  c.utime = kT0;
  c.frame_id = "base";
  for (int i = 0; i < 40; ++i) {
    const float x = 3.0f + 0.1f * static_cast<float>(i);
    for (float z : {0.0f, 0.3f, 0.6f, 1.0f}) {  // floor, then the box's face at x = 4 m
      c.x.push_back(z == 0.0f ? x : 4.0f);
      c.y.push_back(-1.0f + 0.05f * static_cast<float>(i));
      c.z.push_back(z);
    }
  }
  c.num_points = static_cast<int32_t>(c.x.size());
  for (double drift : {0.2, -0.2}) {
    SCOPED_TRACE(drift);
    Preprocessor pre(params.preprocess, fine, coarse);
    PoseBuffer poses;
    auto p = truePose(kT0);
    p.x = 0.0, p.yaw = 0.0, p.qw = 1.0, p.qz = 0.0, p.vx = 0.0, p.wz = 0.0;
    p.z = drift;
    ASSERT_EQ(poses.add(p), PoseBuffer::AddResult::kAdded);
    Frame f;
    pre.process(c, *poses.at(kT0, 0.1), poses, 0.1, &f);
    ASSERT_FALSE(f.points.empty());
    double lowest = INFINITY;
    for (const auto& q : f.points) lowest = std::min(lowest, double(q.z()) - drift);
    EXPECT_GT(lowest, params.preprocess.min_height);  // no floor point
    EXPECT_LT(lowest, 0.45);                          // the box's lowest row (0.3 m) is there
  }
}
