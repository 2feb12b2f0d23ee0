// The LiDAR-inertial odometry on synthetic data with an exactly known motion: start-up from
// a standstill (and refusal while moving), accuracy while driving through a room, IMU-only
// coasting and invalidity when frames stop, IMU gaps, bad samples and frames, determinism,
// and the two baselines (IMU dead reckoning, LiDAR only).
#include <gtest/gtest.h>

#include <cmath>

#include "synthetic_run.hpp"
#include "ucon/lio/lidar_only_odometry.hpp"
#include "ucon/lio/lio_odometry.hpp"

using namespace ucon;
using namespace ucon::lio;

namespace {

test::SyntheticOptions noisy() {
  test::SyntheticOptions o;
  o.gyro_noise_sigma = 0.002;
  o.acc_noise_sigma = 0.02;
  o.gyro_bias = Eigen::Vector3d(0.003, -0.002, 0.004);
  o.acc_bias = Eigen::Vector3d(0.05, -0.04, 0.06);
  o.range_noise_sigma = 0.02;
  return o;
}

LioParams params() {
  LioParams p;
  p.initial_pose = Eigen::Vector3d(0.0, 0.0, 0.0);
  return p;
}

double yawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

// One sample, then the frames it lets run (as the node does).
std::optional<PoseEstimate> feed(LioOdometry& odo, const ImuSample& s, std::vector<FrameReport>* reports) {
  auto e = odo.addImu(s);
  odo.runDueFrames(reports);
  return e;
}

}  // namespace

TEST(LioOdometry, GivenAStandstillThenItInitialisesAtTheConfiguredPoseWithinTheWindow) {
  test::SyntheticOptions o = noisy();
  const Eigen::Vector3d start(1.0, -2.0, 0.7);
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(100.0, 0.0, 0.0, start), o);
  LioParams p = params();
  p.initial_pose = start;
  LioOdometry odo(p);
  std::optional<PoseEstimate> first;
  for (int i = 0; i <= 120 && !first; ++i) {
    first = odo.addImu(run.imu(i * 0.005));
    if (!first) {
      EXPECT_NE(odo.phase(), Phase::kRunning);
    }
  }
  ASSERT_TRUE(first);
  EXPECT_LE(first->t_ns, 510000000) << "initialised after the 0.5 s window";
  EXPECT_TRUE(first->valid);
  EXPECT_NEAR((odo.basePosition(first->x) - Eigen::Vector3d(1.0, -2.0, 0.0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(yawOf(first->x.R), 0.7, 1e-3);
  EXPECT_NEAR((first->x.bg - o.gyro_bias).norm(), 0.0, 1e-3);  // the standstill mean
  // Ground prior (the default): the base starts level and the horizontal specific force at
  // rest is accelerometer bias.
  const Eigen::Vector3d rpy = rpyFromRotation(first->x.R);
  EXPECT_NEAR(rpy.x(), 0.0, 1e-12);
  EXPECT_NEAR(rpy.y(), 0.0, 1e-12);
  EXPECT_NEAR((first->x.ba - o.acc_bias).norm(), 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(first->P(kRot, kRot)), p.ground_tilt_std, 1e-12);

  // Without it, roll and pitch come from gravity's direction and absorb the horizontal bias
  // (0.05 m/s^2 ~ 0.3 deg); only the bias along gravity is estimated.
  p.ground_prior = false;
  LioOdometry free(p);
  std::optional<PoseEstimate> e;
  for (int i = 0; i <= 120 && !e; ++i) e = free.addImu(run.imu(i * 0.005));
  ASSERT_TRUE(e);
  const Eigen::Vector3d rpy2 = rpyFromRotation(e->x.R);
  EXPECT_NEAR(rpy2.x(), o.acc_bias.y() / 9.80665, 5e-4);
  EXPECT_NEAR(rpy2.y(), -o.acc_bias.x() / 9.80665, 5e-4);
  EXPECT_NEAR(e->x.ba.head<2>().norm(), 0.0, 0.01);
}

TEST(LioOdometry, GivenAStartWhileMovingThenNoPoseAndTheStatusSaysWhy) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(0.0, 1.0, 0.5), noisy());
  LioOdometry odo(params());
  int poses = 0;
  std::vector<FrameReport> reports;
  run.run(odo, 1.0, [&](const PoseEstimate&) { ++poses; }, &reports);
  EXPECT_EQ(poses, 0);
  EXPECT_EQ(odo.phase(), Phase::kMovingAtStart);
  EXPECT_NE(odo.phaseReason().find("moving at start"), std::string::npos) << odo.phaseReason();
  ASSERT_FALSE(reports.empty());
  for (const auto& r : reports) EXPECT_EQ(r.result, FrameResult::kNotInitialised);
}

TEST(LioOdometry, GivenADriveThroughARoomThenThePoseFollowsTheTruthWithinCentimetres) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(1.0, 1.0, 0.6), noisy());
  LioOdometry odo(params());
  std::vector<FrameReport> reports;
  PoseEstimate last;
  double worst = 0.0;
  int invalid_after_init = 0;
  run.run(odo, 7.0, [&](const PoseEstimate& e) {
    last = e;
    if (!e.valid) ++invalid_after_init;
    const Eigen::Isometry3d T = run.basePose(e.t_ns * 1e-9);
    worst = std::max(worst, (odo.basePosition(e.x) - T.translation()).norm());
  }, &reports);
  EXPECT_EQ(invalid_after_init, 0);
  const Eigen::Isometry3d T = run.basePose(last.t_ns * 1e-9);
  const double err = (odo.basePosition(last.x) - T.translation()).norm();
  const double yaw_err = std::fabs(std::remainder(yawOf(last.x.R) - yawOf(T.linear()), 2 * M_PI));
  const double path = (T.translation()).norm();
  std::printf("after %.1f m: position error %.3f m (worst %.3f m), yaw error %.3f deg, bias error %.4f rad/s\n", path,
              err, worst, yaw_err * 180 / M_PI, (last.x.bg - noisy().gyro_bias).norm());
  EXPECT_GT(path, 5.0);
  EXPECT_LT(err, 0.05);
  EXPECT_LT(worst, 0.08);
  EXPECT_LT(yaw_err, 0.5 * M_PI / 180.0);
  int updated = 0;
  for (const auto& r : reports) updated += r.result == FrameResult::kUpdated;
  EXPECT_GT(updated, 300);
  std::size_t first = 0;  // frames before the start are not registered...
  while (first < reports.size() && reports[first].result == FrameResult::kNotInitialised) ++first;
  ASSERT_LT(first, reports.size());
  // ... but those of the standstill make the first map, which the first frame registers against.
  EXPECT_EQ(reports[first].result, FrameResult::kUpdated);
  EXPECT_GE(odo.counters().standstill_frames, 20);  // 0.5 s of 50 Hz frames, less the edges
  // Consistency: the stated position std is not wildly below the actual error.
  const double std_xy = std::sqrt(last.P(kPos, kPos) + last.P(kPos + 1, kPos + 1));
  EXPECT_GT(std_xy, 1e-4);
  // The reported constraint: a room constrains every direction.
  EXPECT_GT(reports.back().info_translation.minCoeff(), 1e3);
  EXPECT_GT(reports.back().points_matched, reports.back().points_used / 2);
}

// A large open scene keeps many points after downsampling; max_points bounds the update's work
// with evenly spaced ones of them (all directions kept: the room stays constrained every way).
TEST(LioOdometry, GivenMorePointsThanMaxPointsThenEvenlySpacedOnesOfThemRegister) {
  LioParams all = params();
  all.max_points = 0;
  int fewest = 1 << 30;
  {
    test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(1.0, 1.0, 0.6), noisy());
    LioOdometry odo(all);
    std::vector<FrameReport> reports;
    run.run(odo, 3.0, [](const PoseEstimate&) {}, &reports);
    for (const auto& r : reports)
      if (r.result == FrameResult::kUpdated) fewest = std::min(fewest, r.points_used);
  }
  ASSERT_GT(fewest, 300) << "the synthetic room keeps more than the cap below";

  LioParams capped = params();
  capped.max_points = 150;
  ASSERT_EQ(capped.validate(), "");
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(1.0, 1.0, 0.6), noisy());
  LioOdometry odo(capped);
  std::vector<FrameReport> reports;
  PoseEstimate last;
  run.run(odo, 3.0, [&](const PoseEstimate& e) { last = e; }, &reports);
  int updated = 0;
  for (const auto& r : reports) {
    if (r.result != FrameResult::kUpdated) continue;
    ++updated;
    EXPECT_EQ(r.points_used, 150);
    EXPECT_GT(r.info_translation.minCoeff(), 1e3) << "a direction lost: the kept points are not spread";
  }
  EXPECT_GT(updated, 100);
  const Eigen::Isometry3d T = run.basePose(last.t_ns * 1e-9);
  EXPECT_LT((odo.basePosition(last.x) - T.translation()).norm(), 0.05);

  capped.max_points = capped.min_points - 1;
  EXPECT_NE(capped.validate().find("points.max_points"), std::string::npos);
}

TEST(LioOdometry, GivenFramesStopThenImuOnlyForHalfASecondThenInvalidUntilFramesReturn) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(1.0, 0.8, 0.4), noisy());
  LioOdometry odo(params());
  std::vector<FrameReport> reports;
  run.run(odo, 3.0, nullptr, &reports);
  // 1 s of IMU only.
  std::vector<PoseEstimate> coast;
  for (int i = 601; i <= 800; ++i) {
    if (auto e = feed(odo, run.imu(i * 0.005), &reports)) coast.push_back(*e);
  }
  ASSERT_EQ(coast.size(), 200u);
  const int64_t last_update = odo.stateTimeNs();
  for (const auto& e : coast) {
    const double since = (e.t_ns - last_update) * 1e-9;
    EXPECT_EQ(e.valid, since <= 0.5 + 1e-9) << since;
  }
  // The stated uncertainty grows while coasting.
  EXPECT_GT(coast.back().P(kPos, kPos), 10.0 * coast.front().P(kPos, kPos));
  // Frames again: valid after the first update.
  std::optional<PoseEstimate> back;
  std::vector<FrameReport> later;
  for (int k = 200; k < 215; ++k) {
    for (int i = 0; i < 4; ++i)
      if (auto e = feed(odo, run.imu(4.0 + (k - 200) * 0.02 + (i + 1) * 0.005), &later)) back = e;
    odo.addFrame(run.frame(4.0 + (k - 200) * 0.02), &later);
  }
  ASSERT_TRUE(back);
  EXPECT_TRUE(back->valid);
  ASSERT_FALSE(later.empty());
  EXPECT_EQ(later.back().result, FrameResult::kUpdated);
  const Eigen::Isometry3d T = run.basePose(back->t_ns * 1e-9);
  EXPECT_LT((odo.basePosition(back->x) - T.translation()).norm(), 0.1);
}

TEST(LioOdometry, GivenAnImuGapThenItIsReportedAndTheCovarianceInflated) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(100.0, 0.0, 0.0), noisy());
  LioOdometry a(params()), b(params());
  for (int i = 0; i <= 200; ++i) {
    a.addImu(run.imu(i * 0.005));
    b.addImu(run.imu(i * 0.005));
  }
  std::optional<PoseEstimate> ea, eb;
  for (int i = 201; i <= 260; ++i) {
    ea = a.addImu(run.imu(i * 0.005));
    if (i < 220 || i > 240) eb = b.addImu(run.imu(i * 0.005));  // 105 ms missing
  }
  EXPECT_EQ(a.counters().imu_gaps, 0);
  EXPECT_EQ(b.counters().imu_gaps, 1);
  ASSERT_TRUE(ea && eb);
  EXPECT_GT(eb->P(kVel, kVel), 2.0 * ea->P(kVel, kVel));
  EXPECT_GT(eb->P(kRot + 2, kRot + 2), ea->P(kRot + 2, kRot + 2));
  // A gap over max_imu_gap_s: re-initialise at the last pose, no pose until still again.
  EXPECT_FALSE(b.addImu(run.imu(2.5)));  // 1.2 s after the last one
  EXPECT_EQ(b.counters().reinitialisations, 1);
  EXPECT_EQ(b.phase(), Phase::kInitialising);
  std::optional<PoseEstimate> again;
  for (int i = 501; i <= 620 && !again; ++i) again = b.addImu(run.imu(i * 0.005));
  ASSERT_TRUE(again);
  EXPECT_NEAR(b.basePosition(again->x).head<2>().norm(), 0.0, 0.01);
}

TEST(LioOdometry, GivenBadSamplesThenTheyAreDroppedAndCounted) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(100.0, 0.0, 0.0), noisy());
  LioOdometry odo(params());
  for (int i = 0; i <= 120; ++i) odo.addImu(run.imu(i * 0.005));
  ASSERT_EQ(odo.phase(), Phase::kRunning);
  ImuSample s = run.imu(0.605);
  s.acc.x() = NAN;
  EXPECT_FALSE(odo.addImu(s));
  EXPECT_FALSE(odo.addImu(run.imu(0.595)));  // older than the last one
  EXPECT_FALSE(odo.addImu(run.imu(0.600)));  // same time
  EXPECT_TRUE(odo.addImu(run.imu(0.605)));
  EXPECT_EQ(odo.counters().imu_non_finite, 1);
  EXPECT_EQ(odo.counters().imu_out_of_order, 2);

  std::vector<FrameReport> reports;
  odo.addFrame(run.frame(0.60), &reports);  // ends at 0.62: waits for IMU
  EXPECT_TRUE(reports.empty());
  odo.addFrame(run.frame(0.58), &reports);  // ends before the queued one
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].result, FrameResult::kOutOfOrder);
  PointFrame tiny = run.frame(0.62);
  tiny.points.resize(20);
  tiny.dt_ns.resize(20);
  tiny.dt_ns.back() = 19990000;  // still a 20 ms frame
  odo.addFrame(tiny, &reports);
  for (int i = 122; i <= 130; ++i) feed(odo, run.imu(i * 0.005), &reports);
  ASSERT_EQ(reports.size(), 3u);
  EXPECT_EQ(reports[1].result, FrameResult::kMapStarted);
  EXPECT_EQ(reports[2].result, FrameResult::kTooFewPoints);
  EXPECT_LE(reports[2].points_used, 20);
}

TEST(LioOdometry, GivenTheSameInputTwiceThenTheSameOutputBitForBit) {
  auto once = [] {
    test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(0.7, 1.0, 0.5), noisy());
    LioOdometry odo(params());
    std::vector<double> out;
    run.run(odo, 2.0, [&](const PoseEstimate& e) {
      out.insert(out.end(), e.x.p.data(), e.x.p.data() + 3);
      out.insert(out.end(), e.P.data(), e.P.data() + 15);
    }, nullptr);
    return out;
  };
  const auto a = once(), b = once();
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

TEST(LioBaselines, GivenTheSameDriveThenDeadReckoningAndLidarOnlyBothFollowIt) {
  // The synthetic IMU has constant biases only (no walk), which the standstill start absorbs:
  // dead reckoning stays close for a few seconds here; in the simulator's runs it does not.
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(1.0, 1.0, 0.4), noisy());
  LioOdometry imu_only(params(), LioOdometry::Options{false});
  LidarOnlyOdometry lidar_only(params());
  PoseEstimate last;
  LidarOnlyOdometry::Result lo;
  const double dti = 0.005, dtf = 0.02;
  int i = 0, k = 0, registered = 0, frames = 0;
  while (i * dti <= 3.5) {
    if ((k + 1) * dtf <= i * dti) {
      lo = lidar_only.addFrame(run.frame(k * dtf));
      registered += lo.registered;
      ++frames;
      ++k;
    } else {
      if (auto e = imu_only.addImu(run.imu(i * dti))) last = *e;
      ++i;
    }
  }
  std::vector<FrameReport> none;
  imu_only.addFrame(run.frame(3.5), &none);
  EXPECT_TRUE(none.empty());  // no LiDAR updates in dead reckoning
  const Eigen::Vector3d truth = run.basePose(last.t_ns * 1e-9).translation();
  const double imu_err = (imu_only.basePosition(last.x) - truth).norm();
  const double lidar_err = (lo.T.translation() - run.basePose(lo.t_ns * 1e-9).translation()).norm();
  std::printf("after %.1f m: IMU dead reckoning off by %.3f m, LiDAR only by %.3f m\n", truth.norm(), imu_err, lidar_err);
  EXPECT_GT(truth.norm(), 1.5);
  EXPECT_LT(imu_err, 0.3);
  EXPECT_LT(lidar_err, 0.1);
  EXPECT_EQ(registered, frames);
}

TEST(LioOdometry, GivenFramesDuringTheStartUpStandstillThenTheFirstMapIsBuiltFromThemAll) {
  // One frame makes a sparse map (its floor planes fitted from few points) against which the
  // frame tilts, and the tilt carries into every later part of the map. The frames of the
  // standstill were all taken at the start pose: the map starts from all of them.
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(100.0, 0.0, 0.0), noisy());
  std::vector<FrameReport> reports;
  LioOdometry odo(params());
  for (int i = 0; i <= 140; ++i) {
    const double t = i * 0.005;
    if (i % 4 == 0 && t >= 0.02) odo.addFrame(run.frame(t - 0.02), &reports);  // the frame that just ended
    feed(odo, run.imu(t), &reports);
  }
  ASSERT_EQ(odo.phase(), Phase::kRunning);
  const int64_t still = odo.counters().standstill_frames;
  EXPECT_GE(still, 20);
  EXPECT_LE(still, 26);
  // The map holds far more than one frame's points, and the first frame after the start
  // registered against it (no "map started").
  int not_initialised = 0, updated = 0, started = 0;
  for (const auto& r : reports) {
    not_initialised += r.result == FrameResult::kNotInitialised;
    updated += r.result == FrameResult::kUpdated;
    started += r.result == FrameResult::kMapStarted;
  }
  EXPECT_EQ(started, 0);
  EXPECT_GT(updated, 0);
  EXPECT_GE(not_initialised, still);
  const auto single = [&] {
    LioOdometry one(params());
    std::vector<FrameReport> r;
    for (int i = 0; i <= 140; ++i) {  // the same run, but the LiDAR starts after the start-up
      const double t = i * 0.005;
      if (i % 4 == 0 && t >= 0.62) one.addFrame(run.frame(t - 0.02), &r);
      feed(one, run.imu(t), &r);
    }
    EXPECT_EQ(one.counters().standstill_frames, 0);
    EXPECT_FALSE(r.empty());
    if (!r.empty()) {
      EXPECT_EQ(r.front().result, FrameResult::kMapStarted);
    }
    return one.map().numPoints();
  }();
  EXPECT_GT(odo.map().numPoints(), 2 * single);
}

TEST(LioOdometry, GivenAPersonWalkingThroughTheRoomThenTheTraceLeavesTheMapAndTheRoomStays) {
  // A person walks 1 m/s along x = 6.2 while the robot drives: without carving their points
  // stay in the map along the way; with it most of the trace behind them is gone and the room's
  // structure is not. What stays shares a voxel with the floor (the floor's points keep it) or
  // lies where the rays beyond it go to the open sky (the room has no ceiling): no evidence.
  world::Scenario sc = test::roomScenario();
  world::MovingObstacle person;
  person.radius = 0.25;
  person.motion.position = Eigen::Vector2d(6.2, -4.0);
  person.motion.velocity = Eigen::Vector2d(0.0, 1.0);
  sc.movers.push_back(person);
  auto traceAndTotal = [](const world::Scenario& s, int carve_every, int64_t* carved) {
    test::SyntheticRun run(world::World(s), test::curvyDrive(1.0, 1.0, 0.6), noisy());
    LioParams p = params();
    p.map_carve_every = carve_every;
    LioOdometry odo(p);
    run.run(odo, 7.0, [](const PoseEstimate&) {}, nullptr);
    std::size_t trace = 0;  // where the person was more than 1.5 s before the end
    for (const Eigen::Vector3f& q : odo.map().points())
      if (std::fabs(q.x() - 6.2f) < 0.5f && q.y() > -4.5f && q.y() < 1.5f && q.z() > 0.3f && q.z() < 1.5f) {
        ++trace;
      }
    *carved = odo.counters().map_voxels_carved;
    return std::make_pair(trace, odo.map().numPoints());
  };
  int64_t carved_off = 0, carved_on = 0, carved_static = 0;
  const auto off = traceAndTotal(sc, 0, &carved_off);
  const auto on = traceAndTotal(sc, LioParams{}.map_carve_every, &carved_on);
  const auto room = traceAndTotal(test::roomScenario(), LioParams{}.map_carve_every, &carved_static);
  std::printf("trace points: %zu without carving, %zu with (%lld voxels carved); map %zu / %zu points, "
              "room alone %zu (%lld carved)\n",
              off.first, on.first, static_cast<long long>(carved_on), off.second, on.second, room.second,
              static_cast<long long>(carved_static));
  EXPECT_EQ(carved_off, 0);
  EXPECT_GT(off.first, 50u);
  EXPECT_LT(on.first, off.first / 4);
  EXPECT_GT(carved_on, 0);
  // The room itself barely loses anything.
  const auto room_off = traceAndTotal(test::roomScenario(), 0, &carved_off);
  std::printf("room alone: %zu points with carving, %zu without\n", room.second, room_off.second);
  EXPECT_GT(static_cast<double>(room.second), 0.97 * static_cast<double>(room_off.second));
}
