// ucon-odometry's node: the shipped config equals the defaults, the base pose and its
// covariance (Jacobian against finite differences), and the node's handling of messages —
// standstill start, poses at IMU rate, a status per frame, bad input counted and dropped.
#include <gtest/gtest.h>

#include <cmath>

#include "synthetic_run.hpp"
#include "ucon/config.hpp"
#include "ucon/odometry/odometry_node.hpp"
#include "ucon/odometry/params.hpp"
#include "ucon/runtime/config_file.hpp"

using namespace ucon;
using namespace ucon::odometry;

namespace {

OdometryParams shipped() {
  std::string err;
  const auto text = runtime::readTextFile("deploy/config/odometry.yaml", &err);
  EXPECT_TRUE(text) << err;
  std::vector<ConfigError> errors;
  const auto p = loadParams<OdometryParams>(text ? *text : "", "odometry.yaml", &errors);
  EXPECT_TRUE(p) << (errors.empty() ? "" : errors[0].toString());
  return p ? *p : OdometryParams{};
}

// Message time of synthetic time 0 (utime 0 means invalid on the bus).
constexpr int64_t kT0 = 1000000;

imu_t toImu(const lio::ImuSample& s, const std::string& frame = "base") {
  imu_t m{};
  m.utime = kT0 + s.t_ns / 1000;
  m.frame_id = frame;
  m.gyro_x = s.gyro.x();
  m.gyro_y = s.gyro.y();
  m.gyro_z = s.gyro.z();
  m.acc_x = s.acc.x();
  m.acc_y = s.acc.y();
  m.acc_z = s.acc.z();
  return m;
}

point_cloud_t toCloud(const lio::PointFrame& f, int64_t seq) {
  point_cloud_t c{};
  c.utime = kT0 + f.t0_ns / 1000;
  c.seq = seq;
  c.frame_id = "base";
  c.num_points = static_cast<int32_t>(f.points.size());
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    c.x.push_back(f.points[i].x());
    c.y.push_back(f.points[i].y());
    c.z.push_back(f.points[i].z());
    c.t_offset_ns.push_back(static_cast<int32_t>(f.dt_ns[i]));
    c.reflectivity.push_back(50);
    c.tag.push_back(0);
  }
  c.duration_us = f.dt_ns.empty() ? 0 : static_cast<int32_t>(f.dt_ns.back() / 1000);
  return c;
}

test::SyntheticOptions noisy() {
  test::SyntheticOptions o;
  o.gyro_noise_sigma = 0.0011;
  o.acc_noise_sigma = 0.014;
  o.gyro_bias = Eigen::Vector3d(0.002, 0.003, -0.0015);
  o.range_noise_sigma = 0.02;
  return o;
}

}  // namespace

TEST(OdometryParams, GivenTheShippedConfigThenEveryKeyIsReadAndBadValuesAreNamed) {
  std::string err;
  const std::string text = *runtime::readTextFile("deploy/config/odometry.yaml", &err);
  struct Case {
    std::string from, to, key;
  };
  for (const Case& c : std::vector<Case>{{"window_s: 0.5", "window_s: 1.5", "init.window_s"},
                                         {"knn: 5", "knn: 12", "update.knn"},
                                         {"neighbourhood: 6", "neighbourhood: 7", "map.neighbourhood"},
                                         {"max_range: 40.0", "max_range: 0.2", "points.max_range"},
                                         {"max_points: 1000", "max_points: 50", "points.max_points"},
                                         {"radius: 60.0", "radius: 30.0", "map.radius"},
                                         {"pose_channel: ROBOT_POSE", "pose_channel: POSE", "pose_channel"},
                                         {"gap_s: 0.05", "gap_s: 0.05\n  gap_ss: 1", "imu.gap_ss"}}) {
    std::string t = text;
    const auto pos = t.find(c.from);
    ASSERT_NE(pos, std::string::npos) << c.from;
    t.replace(pos, c.from.size(), c.to);
    std::vector<ConfigError> errors;
    EXPECT_FALSE(loadParams<OdometryParams>(t, "odometry.yaml", &errors)) << c.to;
    bool named = false;
    for (const auto& e : errors) named = named || e.key == c.key;
    EXPECT_TRUE(named) << c.to << " -> " << (errors.empty() ? "no error" : errors[0].toString());
  }
}

TEST(OdometryParams, GivenAStartPoseThenTheConfigTextCarriesItAndLoads) {
  std::string err;
  const std::string text = *runtime::readTextFile("deploy/config/odometry.yaml", &err);
  const auto patched = withInitialPose(text, Eigen::Vector3d(-22.0, 3.25, 0.1));
  ASSERT_TRUE(patched);
  std::vector<ConfigError> errors;
  const auto p = loadParams<OdometryParams>(*patched, "odometry.yaml", &errors);
  ASSERT_TRUE(p) << (errors.empty() ? "" : errors[0].toString());
  EXPECT_EQ(p->lio.initial_pose, Eigen::Vector3d(-22.0, 3.25, 0.1));
  EXPECT_NE(patched->find("# base x [m]"), std::string::npos);  // the comment stays
  EXPECT_FALSE(withInitialPose("points_frame: base\n", Eigen::Vector3d::Zero()));
}

TEST(BasePose, GivenTheJacobianThenItMatchesFiniteDifferences) {
  lio::NavState x;
  x.R = lio::rotationFromRpy(0.05, -0.08, 2.4);
  x.p = Eigen::Vector3d(3.0, -1.0, 0.6);
  const Eigen::Vector3d t(0.011, -0.023, 0.544);
  const auto M = basePoseJacobian(x, t);
  const double h = 1e-6;
  for (int i = 0; i < lio::kStateDim; ++i) {
    lio::Vector15 d = lio::Vector15::Zero();
    d[i] = h;
    const Eigen::Matrix<double, 6, 1> col =
        (basePoseVector(lio::boxplus(x, d), t) - basePoseVector(lio::boxplus(x, -d), t)) / (2 * h);
    EXPECT_NEAR((col - M.col(i)).norm(), 0.0, 1e-7) << "column " << i;
  }
}

TEST(BasePose, GivenAnEstimateThenRobotPoseCarriesTheBaseAndA6x6Covariance) {
  lio::PoseEstimate e;
  e.t_ns = 1234567000;
  e.valid = true;
  const Eigen::Vector3d t(0.011, -0.023, 0.544);
  e.x.R = lio::rotationFromRpy(0, 0, M_PI / 2);
  e.x.p = Eigen::Vector3d(1.0, 2.0, 0.0) + e.x.R * t;
  e.x.v = Eigen::Vector3d(0.5, 0.0, 0.0);
  e.omega = Eigen::Vector3d(0, 0, 1.0);
  e.P = lio::Matrix15::Identity() * 1e-4;
  const robot_pose_t m = toRobotPose(e, t);
  EXPECT_EQ(m.utime, 1234567);
  EXPECT_TRUE(m.valid);
  EXPECT_NEAR(m.x, 1.0, 1e-12);
  EXPECT_NEAR(m.y, 2.0, 1e-12);
  EXPECT_NEAR(m.z, 0.0, 1e-12);
  EXPECT_NEAR(m.yaw, M_PI / 2, 1e-12);
  EXPECT_NEAR(m.qz, std::sqrt(0.5), 1e-12);
  // v_base = v_imu - R (w x t): turning at 1 rad/s, the IMU 1.1 cm ahead and 2.3 cm right.
  const Eigen::Vector3d vb = e.x.v - e.x.R * e.omega.cross(t);
  EXPECT_NEAR(m.vx, vb.x(), 1e-12);
  EXPECT_NEAR(m.vy, vb.y(), 1e-12);
  ASSERT_EQ(m.cov_size, 36);
  EXPECT_GT(m.cov[0], 1e-4);  // position plus the lever arm's share of attitude
  EXPECT_NEAR(m.cov[35], 1e-4, 1e-9);  // yaw
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) EXPECT_EQ(m.cov[static_cast<std::size_t>(r * 6 + c)], m.cov[static_cast<std::size_t>(c * 6 + r)]);
}

TEST(OdometryNode, GivenAStandstillAndADriveThenPosesAtImuRateAndAStatusPerFrame) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(1.0, 1.0, 0.4), noisy());
  OdometryNode node(shipped());
  std::vector<robot_pose_t> poses;
  std::vector<odometry_status_t> statuses;
  auto take = [&](const OdometryOutput& o) {
    if (o.pose) poses.push_back(*o.pose);
    statuses.insert(statuses.end(), o.statuses.begin(), o.statuses.end());
  };
  int imu = 0, frames = 0;
  for (int i = 0, k = 0; i <= 600;) {
    if ((k + 1) * 0.02 <= i * 0.005) {
      take(node.onPoints(toCloud(run.frame(k * 0.02), k)));
      ++k, ++frames;
    } else {
      take(node.onImu(toImu(run.imu(i * 0.005))));
      take(node.processFrames());
      ++i, ++imu;
    }
  }
  // Start-up: 0.5 s of standstill, then one pose per sample, valid.
  ASSERT_FALSE(poses.empty());
  EXPECT_LE(poses.front().utime - kT0, 510000);
  EXPECT_EQ(static_cast<int>(poses.size()), imu - static_cast<int>((poses.front().utime - kT0) / 5000));
  for (std::size_t i = 1; i < poses.size(); ++i) {
    EXPECT_EQ(poses[i].utime - poses[i - 1].utime, 5000);
    EXPECT_EQ(poses[i].seq, poses[i - 1].seq + 1);
    EXPECT_TRUE(poses[i].valid);
  }
  // A status per frame: frames before the start say why they were dropped.
  EXPECT_EQ(static_cast<int>(statuses.size()), frames);
  EXPECT_EQ(statuses.front().result, odometry_status_t::RESULT_NOT_INITIALISED);
  EXPECT_NE(statuses.front().message.find("standstill"), std::string::npos) << statuses.front().message;
  int updated = 0;
  for (const auto& s : statuses) updated += s.result == odometry_status_t::RESULT_UPDATED;
  EXPECT_GT(updated, 100);
  const odometry_status_t& last = statuses.back();
  EXPECT_EQ(last.state, odometry_status_t::STATE_RUNNING);
  EXPECT_TRUE(last.valid);
  EXPECT_GT(last.points_matched, 100);
  EXPECT_LT(last.residual_rms, 0.05);
  EXPECT_LT(last.std_x, 0.05);
  const Eigen::Isometry3d T = run.basePose((poses.back().utime - kT0) * 1e-6);
  EXPECT_LT(std::hypot(poses.back().x - T.translation().x(), poses.back().y - T.translation().y()), 0.05);
  // The health message counts what happened.
  auto& st = node.status();
  EXPECT_EQ(st.counter("poses_out"), static_cast<int64_t>(poses.size()));
  EXPECT_EQ(st.counter("frames_updated"), updated);
}

TEST(OdometryNode, GivenBadInputThenItIsCountedAndDroppedNeverAPoseThatJumps) {
  test::SyntheticRun run(world::World(test::roomScenario()), test::curvyDrive(100.0, 0.0, 0.0), noisy());
  OdometryNode node(shipped());
  for (int i = 0; i <= 120; ++i) node.onImu(toImu(run.imu(i * 0.005)));
  // Wrong frame, NaN, utime 0, out of order: no pose.
  EXPECT_FALSE(node.onImu(toImu(run.imu(0.605), "lidar")).pose);
  imu_t nan = toImu(run.imu(0.605));
  nan.gyro_z = NAN;
  EXPECT_FALSE(node.onImu(nan).pose);
  imu_t zero = toImu(run.imu(0.605));
  zero.utime = 0;
  EXPECT_FALSE(node.onImu(zero).pose);
  EXPECT_FALSE(node.onImu(toImu(run.imu(0.300))).pose);
  EXPECT_TRUE(node.onImu(toImu(run.imu(0.605))).pose);
  EXPECT_EQ(node.status().counter("imu_wrong_frame"), 1);
  EXPECT_EQ(node.status().counter("imu_non_finite"), 2);
  EXPECT_EQ(node.status().counter("imu_out_of_order"), 1);

  // Frames: wrong frame_id, ragged arrays, NaN points.
  point_cloud_t c = toCloud(run.frame(0.60), 1);
  c.frame_id = "lidar";
  auto out = node.onPoints(c);
  ASSERT_EQ(out.statuses.size(), 1u);
  EXPECT_EQ(out.statuses[0].result, odometry_status_t::RESULT_BAD_FRAME);
  EXPECT_NE(out.statuses[0].message.find("frame_id"), std::string::npos);
  c = toCloud(run.frame(0.60), 2);
  c.x.pop_back();
  EXPECT_EQ(node.onPoints(c).statuses.at(0).result, odometry_status_t::RESULT_BAD_FRAME);
  c = toCloud(run.frame(0.60), 3);
  for (int i = 0; i < 10; ++i) c.z[static_cast<std::size_t>(i)] = NAN;
  c.t_offset_ns[10] = -5;
  EXPECT_TRUE(node.onPoints(c).statuses.empty());  // queued: waits for IMU up to its end
  std::vector<odometry_status_t> st;
  std::vector<robot_pose_t> poses;
  for (int i = 122; i <= 140; ++i) {
    auto o = node.onImu(toImu(run.imu(i * 0.005)));
    if (o.pose) poses.push_back(*o.pose);
    for (auto& s : node.processFrames().statuses) st.push_back(s);
  }
  ASSERT_EQ(st.size(), 1u);
  EXPECT_EQ(st[0].result, odometry_status_t::RESULT_MAP_STARTED);
  EXPECT_EQ(st[0].points_dropped, 11);
  EXPECT_EQ(node.status().counter("points_dropped"), 11);
  // IMU gap of 100 ms: the next pose says so through its covariance, and the frame's status
  // reports the gap.
  const double before = poses.back().cov[0];
  auto o = node.onImu(toImu(run.imu(0.80)));
  ASSERT_TRUE(o.pose);
  EXPECT_GT(o.pose->cov[0], before);
  EXPECT_EQ(node.status().counter("imu_gaps"), 1);
  EXPECT_NEAR(o.pose->x, 0.0, 0.01);  // standing still: no jump
}
