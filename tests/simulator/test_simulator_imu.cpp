// The simulated Mid-360 IMU: the configured bias and noise at rest, the bias random walk, the
// lever arm of the IMU's offset from the LiDAR origin when turning, the clock offset, the
// vibration's rates, and pose_source none (no ROBOT_POSE, ground truth as before).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ucon/livox/protocol.hpp"
#include "ucon/simulator/simulator.hpp"

using namespace ucon;
using namespace ucon::simulator;

namespace {

world::Scenario openRoom() {
  world::Scenario s;
  s.name = "open";
  s.bounds = world::Bounds{-10, 10, -10, 10};
  s.statics.push_back(world::makeWall(world::Vec2(-10, 8), world::Vec2(10, 8), 0.2, 2.5));
  return s;
}

SimulatorParams quiet() {
  SimulatorParams p;
  p.base.geometry.max_wheel_speed = 40.0;
  p.imu.gyro_noise_sigma = 0.0;
  p.imu.acc_noise_sigma = 0.0;
  p.imu.gyro_bias_walk = 0.0;
  p.imu.acc_bias_walk = 0.0;
  return p;
}

struct Imu {
  uint64_t stamp_ns;
  Eigen::Vector3d gyro, acc;  // sensor frame, SI
};

std::vector<Imu> parseImu(const SimOutputs& out) {
  std::vector<Imu> v;
  livox::ParsedPacket pk;
  for (const auto& d : out.imu_packets) {
    EXPECT_EQ(livox::parsePacket(d.bytes.data(), d.bytes.size(), pk), livox::ParseStatus::kOk);
    v.push_back({pk.header.timestamp_ns, Eigen::Vector3d(pk.imu.gyro_x, pk.imu.gyro_y, pk.imu.gyro_z),
                 Eigen::Vector3d(pk.imu.acc_x, pk.imu.acc_y, pk.imu.acc_z)});
  }
  return v;
}

int64_t us(double s) { return static_cast<int64_t>(std::llround(s * 1e6)); }

}  // namespace

TEST(SimulatorImu, GivenTheRobotAtRestThenSamplesShowTheConfiguredBiasAndNoise) {
  SimulatorParams p = quiet();
  p.imu.gyro_noise_sigma = 0.0011;
  p.imu.acc_noise_sigma = 0.014;
  Simulator sim(p, openRoom());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(5.0), out);
  const auto s = parseImu(out);
  ASSERT_EQ(s.size(), 1001u);
  Eigen::Vector3d mg = Eigen::Vector3d::Zero(), ma = Eigen::Vector3d::Zero();
  for (const auto& x : s) {
    mg += x.gyro;
    ma += x.acc;
  }
  mg /= static_cast<double>(s.size());
  ma /= static_cast<double>(s.size());
  double vg = 0, va = 0;
  for (const auto& x : s) {
    vg += (x.gyro - mg).squaredNorm();
    va += (x.acc - ma).squaredNorm();
  }
  vg /= 3.0 * static_cast<double>(s.size());
  va /= 3.0 * static_cast<double>(s.size());
  // Upside down at rest: gravity along -z of the sensor, plus the bias at start.
  const Eigen::Vector3d bg(0.002, -0.003, 0.0015), ba(0.04, -0.03, 0.05);
  EXPECT_NEAR((mg - bg).norm(), 0.0, 2e-4);
  EXPECT_NEAR((ma - (Eigen::Vector3d(0, 0, -9.80665) + ba)).norm(), 0.0, 3e-3);  // g travels as float g
  EXPECT_NEAR(std::sqrt(vg), 0.0011, 0.0001);
  EXPECT_NEAR(std::sqrt(va), 0.014, 0.0013);
}

TEST(SimulatorImu, GivenABiasWalkThenEachStepMovesTheBiasBySigmaTimesTheRootOfTheStep) {
  SimulatorParams p = quiet();
  p.imu.gyro_bias_walk = 0.01;
  p.imu.acc_bias_walk = 0.1;
  Simulator sim(p, openRoom());
  SimOutputs out;
  std::vector<double> dg, da;
  Eigen::Vector3d g = sim.gyroBias(), a = sim.accBias();
  for (int i = 1; i <= 400; ++i) {
    sim.advanceTo(p.start_utime + i * 5000, out);
    for (int k = 0; k < 3; ++k) {
      dg.push_back(sim.gyroBias()[k] - g[k]);
      da.push_back(sim.accBias()[k] - a[k]);
    }
    g = sim.gyroBias();
    a = sim.accBias();
  }
  auto rms = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return std::sqrt(s / static_cast<double>(v.size()));
  };
  EXPECT_NEAR(rms(dg), 0.01 * std::sqrt(0.005), 0.1 * 0.01 * std::sqrt(0.005));
  EXPECT_NEAR(rms(da), 0.1 * std::sqrt(0.005), 0.1 * 0.1 * std::sqrt(0.005));
}

TEST(SimulatorImu, GivenTurningOnTheSpotThenTheImuFeelsTheLeverArmOfItsOffset) {
  SimulatorParams p = quiet();
  p.imu.gyro_bias = {0, 0, 0};
  p.imu.acc_bias = {0, 0, 0};
  Simulator sim(p, openRoom());
  SimOutputs out;
  wheel_cmd_t c{};
  c.enable = true;
  c.w_fl = c.w_rl = -16.0;  // left wheels back, right forward: 2 rad/s counter-clockwise
  c.w_fr = c.w_rr = 16.0;
  for (int k = 0; k <= 15; ++k) {
    sim.onWheelCmd(c);
    sim.advanceTo(p.start_utime + k * 100000, out);
  }
  const double wz = sim.robot().body.wz;
  ASSERT_NEAR(wz, 2.0, 0.01);
  out.clear();
  sim.onWheelCmd(c);
  sim.advanceTo(sim.utime() + 50000, out);
  const auto s = parseImu(out);
  ASSERT_FALSE(s.empty());
  // The IMU is 0.011 m, 0.023 m off the spin axis (sensor x, y; the axis is the sensor's z):
  // a centripetal acceleration of w^2 r towards the axis; upside down, the sensor's z rate is -w.
  const Eigen::Vector2d r(0.011, 0.023);
  for (const auto& x : s) {
    EXPECT_NEAR(x.gyro.z(), -wz, 1e-4);
    EXPECT_NEAR(x.acc.head<2>().norm(), wz * wz * r.norm(), 2e-3);
    EXPECT_LT(x.acc.head<2>().normalized().dot(r.normalized()), -0.99);  // pointing to the axis
  }
}

TEST(SimulatorImu, GivenAClockOffsetThenImuStampsShiftByIt) {
  SimulatorParams p = quiet();
  p.imu.time_offset_s = 0.003;
  Simulator sim(p, openRoom());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(0.1), out);
  const auto s = parseImu(out);
  ASSERT_EQ(s.size(), 21u);
  for (std::size_t i = 0; i < s.size(); ++i)
    EXPECT_EQ(s[i].stamp_ns, static_cast<uint64_t>(p.start_utime) * 1000u + 5000000u * i + 3000000u);
}

TEST(SimulatorImu, GivenVibrationThenTheGyroSeesRollAndPitchRatesAndGroundTruthStaysPlanar) {
  SimulatorParams p = quiet();
  p.imu.gyro_bias = {0, 0, 0};
  p.vibration.amplitude_deg = 0.5;
  p.vibration.frequency_hz = 5.0;
  Simulator sim(p, openRoom());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(1.0), out);
  const auto s = parseImu(out);
  double max_x = 0, max_y = 0;
  for (const auto& x : s) {
    max_x = std::max(max_x, std::fabs(x.gyro.x()));
    max_y = std::max(max_y, std::fabs(x.gyro.y()));
  }
  const double a = 0.5 * M_PI / 180.0, w = 2 * M_PI * 5.0;
  EXPECT_NEAR(max_x, a * w, 0.05 * a * w);          // roll rate amplitude
  EXPECT_NEAR(max_y, 1.37 * a * w, 0.05 * a * w);   // pitch at 1.37 f
  ASSERT_FALSE(out.ground_truth.empty());
  for (const auto& g : out.ground_truth) EXPECT_EQ(g.robot_x, 0.0);
}

TEST(SimulatorImu, GivenPoseSourceNoneThenNoRobotPoseButGroundTruthAsBefore) {
  SimulatorParams p = quiet();
  p.pose_source = "none";
  EXPECT_EQ(p.validate(), "");
  Simulator sim(p, openRoom());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(1.0), out);
  EXPECT_TRUE(out.poses.empty());
  EXPECT_EQ(out.ground_truth.size(), 51u);
  EXPECT_EQ(out.imu_packets.size(), 201u);
  p.pose_source = "odometry";
  EXPECT_NE(p.validate().find("pose_source"), std::string::npos);
}
