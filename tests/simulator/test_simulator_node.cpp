// The simulator node in-process: Livox packets parse back with ucon::livox and carry the right
// header fields; points lie on the simulated surfaces; IMU rate and gravity; the Mecanum
// plant integrates wheel commands; collisions are flagged; same inputs -> same bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ucon/livox/protocol.hpp"
#include "ucon/simulator/simulator.hpp"
#include "ucon/world/scenario_yaml.hpp"

using namespace ucon;
using namespace ucon::simulator;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

world::Scenario pedestrians() {
  world::ScenarioError err;
  auto s = world::parseScenarioYaml(readFile("deploy/scenarios/pedestrians.yaml"), "pedestrians", &err);
  EXPECT_TRUE(s) << err.toString();
  return s ? *s : world::Scenario{};
}

// A box room with one pillar ahead of the robot.
world::Scenario room() {
  world::Scenario s;
  s.name = "room";
  s.bounds = world::Bounds{-10, 10, -10, 10};
  s.robot.start = world::Vec2(0, 0);
  world::StaticObstacle p;
  p.center = world::Vec2(3, 0);
  p.radius = 0.5;
  p.height = 2.0;
  s.statics.push_back(p);
  s.statics.push_back(world::makeWall(world::Vec2(-10, 8), world::Vec2(10, 8), 0.2, 2.5));
  return s;
}

SimulatorParams defaults() {
  SimulatorParams p;
  p.base.geometry.max_wheel_speed = 40.0;
  return p;
}

int64_t us(double s) { return static_cast<int64_t>(std::llround(s * 1e6)); }

}  // namespace

TEST(SimulatorNode, GivenOneSecondThenPointPacketsAreWellFormedAndNumberedPerFrame) {
  SimulatorParams p = defaults();
  Simulator sim(p, pedestrians());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(1.0) - 1, out);
  // 200 000 points/s in packets of 96: one every 480 us.
  ASSERT_EQ(out.point_packets.size(), 2084u);  // t = 0, 480 us, ..., 999.84 ms
  livox::ParsedPacket pk;
  uint64_t prev_ts = 0;
  int prev_frame = -1, expected_udp = 0, frames = 0;
  for (std::size_t j = 0; j < out.point_packets.size(); ++j) {
    const auto& d = out.point_packets[j];
    EXPECT_EQ(d.port, 56301);
    ASSERT_EQ(d.bytes.size(), 1380u);
    ASSERT_EQ(livox::parsePacket(d.bytes.data(), d.bytes.size(), pk), livox::ParseStatus::kOk) << j;
    const auto& h = pk.header;
    EXPECT_EQ(h.version, 0);
    EXPECT_EQ(h.length, 1380);
    EXPECT_EQ(h.dot_num, 96);
    EXPECT_EQ(h.data_type, 1);
    EXPECT_EQ(h.time_type, 0);
    EXPECT_EQ(h.time_interval, 4800);  // 96 points x 5 us in 0.1 us
    EXPECT_EQ(h.timestamp_ns, 1000000000ULL + 480000ULL * j);
    if (j > 0) {
      EXPECT_EQ(h.timestamp_ns - prev_ts, 480000u);
    }
    prev_ts = h.timestamp_ns;
    // Frame = 20 ms: frame_cnt steps and udp_cnt restarts at the first packet of each frame.
    const int frame = static_cast<int>((480000ULL * j) / 20000000ULL);
    if (frame != prev_frame) {
      if (prev_frame >= 0) {
        EXPECT_EQ(h.frame_cnt, static_cast<uint8_t>(frames)) << j;
      }
      expected_udp = 0;
      prev_frame = frame;
      ++frames;
    }
    EXPECT_EQ(h.udp_cnt, expected_udp++) << j;
    // Point times 5 us apart.
    ASSERT_EQ(pk.points.size(), 96u);
    EXPECT_EQ(pk.points[95].time_ns - pk.points[0].time_ns, 95u * 5000u);
  }
  EXPECT_EQ(frames, 50);
  // Ground truth at 50 Hz, poses at 100 Hz, IMU at 200 Hz.
  EXPECT_EQ(out.ground_truth.size(), 50u);
  EXPECT_EQ(out.poses.size(), 100u);
  EXPECT_EQ(out.imu_packets.size(), 200u);
}

TEST(SimulatorNode, GivenNoNoiseThenEveryReturnLiesOnASimulatedSurface) {
  SimulatorParams p = defaults();
  p.lidar.range_noise_sigma = 0.0;
  const world::Scenario scen = pedestrians();
  Simulator sim(p, scen);
  world::World ref(scen);
  SimOutputs out;
  livox::ParsedPacket pk;
  double sum = 0, worst = 0;
  int n = 0, zeros = 0;
  for (int j = 0; j < 400; ++j) {
    out.clear();
    sim.advanceTo(p.start_utime + (j * 480), out);
    ASSERT_EQ(out.point_packets.size(), 1u) << j;
    ASSERT_EQ(livox::parsePacket(out.point_packets[0].bytes.data(), out.point_packets[0].bytes.size(), pk),
              livox::ParseStatus::kOk);
    ref.setTime(j * 480e-6);
    const Eigen::Isometry3d T = sim.sensorPose();
    for (const auto& q : pk.points) {
      if (q.x == 0 && q.y == 0 && q.z == 0) {
        ++zeros;
        continue;
      }
      const Eigen::Vector3d w = T * Eigen::Vector3d(q.x, q.y, q.z);
      const double d = ref.surfaceDistance(w, 1.0);
      sum += d;
      worst = std::max(worst, d);
      ++n;
    }
  }
  ASSERT_GT(n, 35000);  // in a walled room almost every ray returns
  EXPECT_LT(sum / n, 0.002);   // mm rounding only
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(zeros, n / 10);
  // Upside down: the sensor sees the floor around the robot, so points below the sensor exist.
}

TEST(SimulatorNode, GivenRangeNoiseThenPointsScatterAroundTheSurfaceWithTheConfiguredSigma) {
  SimulatorParams p = defaults();
  p.lidar.range_noise_sigma = 0.02;
  const world::Scenario scen = room();
  Simulator sim(p, scen);
  world::World ref(scen);
  SimOutputs out;
  sim.advanceTo(p.start_utime + 100000, out);
  livox::ParsedPacket pk;
  const Eigen::Isometry3d T = sim.sensorPose();
  // Along each point's ray, measured range minus the true (noise-free) range is N(0, sigma).
  double sum = 0, sum2 = 0;
  int n = 0;
  for (const auto& d : out.point_packets) {
    ASSERT_EQ(livox::parsePacket(d.bytes.data(), d.bytes.size(), pk), livox::ParseStatus::kOk);
    for (const auto& q : pk.points) {
      if (q.x == 0 && q.y == 0 && q.z == 0) continue;
      const Eigen::Vector3d ps(q.x, q.y, q.z);
      const double measured = ps.norm();
      const auto hit = ref.castRay(T.translation(), T.linear() * ps / measured, 40.0);
      ASSERT_NE(hit.kind, world::HitKind::kNone);
      const double e = measured - hit.range;
      sum += e;
      sum2 += e * e;
      ++n;
    }
  }
  ASSERT_GT(n, 5000);
  EXPECT_NEAR(sum / n, 0.0, 0.002);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.002);
}

TEST(SimulatorNode, GivenTheUpsideDownMountThenTheFieldOfViewLooksDownAndImuSeesMinusOneG) {
  SimulatorParams p = defaults();
  Simulator sim(p, room());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(1.0), out);
  // Directions: elevation in the sensor frame within [-7, 52] deg; world z flipped.
  LidarEmulator lid(p.lidar);
  double zmin = 1, zmax = -1;
  for (uint64_t k = 0; k < 20000; ++k) {
    const Eigen::Vector3d d = lid.direction(k);
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    zmin = std::min(zmin, d.z());
    zmax = std::max(zmax, d.z());
    const Eigen::Vector3d w = lid.mount().linear() * d;
    EXPECT_NEAR(w.z(), -d.z(), 1e-12);
  }
  EXPECT_NEAR(zmin, std::sin(-7 * M_PI / 180), 1e-3);
  EXPECT_NEAR(zmax, std::sin(52 * M_PI / 180), 1e-3);
  // IMU: 200 Hz, 5 ms apart; a robot at rest upside down measures -1 g along sensor z.
  ASSERT_EQ(out.imu_packets.size(), 201u);
  livox::ParsedPacket pk;
  for (std::size_t i = 0; i < out.imu_packets.size(); ++i) {
    const auto& b = out.imu_packets[i].bytes;
    EXPECT_EQ(out.imu_packets[i].port, 56401);
    ASSERT_EQ(livox::parsePacket(b.data(), b.size(), pk), livox::ParseStatus::kOk);
    EXPECT_EQ(pk.header.data_type, 0);
    EXPECT_EQ(pk.header.timestamp_ns, 1000000000ULL + 5000000ULL * i);
    EXPECT_NEAR(pk.imu.acc_z, -9.80665, 0.1);
    EXPECT_NEAR(pk.imu.acc_x, 0.0, 0.1);
    EXPECT_NEAR(pk.imu.gyro_z, 0.0, 0.01);
    // On the wire acceleration is in g: float at offset 36 + 20 (acc_z).
    float acc_z_g;
    std::memcpy(&acc_z_g, b.data() + 36 + 20, 4);
    EXPECT_NEAR(acc_z_g, -1.0, 0.01);
  }
}

TEST(SimulatorNode, GivenForwardWheelCommandsThenThePlantDrivesWithTheMotorLag) {
  SimulatorParams p = defaults();
  Simulator sim(p, room());
  SimOutputs out;
  wheel_cmd_t c{};
  c.enable = true;
  c.w_fl = c.w_fr = c.w_rl = c.w_rr = 10.0;  // 10 rad/s x 0.05 m = 0.5 m/s forward
  for (int k = 0; k <= 20; ++k) {  // commands every 100 ms for 2 s
    sim.onWheelCmd(c);
    sim.advanceTo(p.start_utime + k * 100000, out);
  }
  // x(t) = v (t - tau (1 - e^{-t/tau})) with tau = 0.05 s.
  const double tau = 0.05, t = 2.0;
  EXPECT_NEAR(sim.robot().x, 0.5 * (t - tau * (1 - std::exp(-t / tau))), 2e-3);
  EXPECT_NEAR(sim.robot().y, 0.0, 1e-9);
  ASSERT_EQ(out.poses.size(), 201u);
  const auto& last = out.poses.back();
  EXPECT_EQ(last.utime, p.start_utime + 2000000);
  EXPECT_TRUE(last.valid);
  EXPECT_NEAR(last.vx, 0.5, 1e-3);
  EXPECT_NEAR(last.qw, 1.0, 1e-12);
  for (std::size_t i = 1; i < out.poses.size(); ++i) EXPECT_EQ(out.poses[i].utime - out.poses[i - 1].utime, 10000);
  // Then silence: the watchdog brakes after cmd_timeout_s.
  out.clear();
  sim.advanceTo(p.start_utime + us(3.5), out);
  EXPECT_NEAR(sim.robot().body.vx, 0.0, 1e-6);
  EXPECT_EQ(sim.counters().cmd_timeouts, 1);
  // Rotation in place: wz = r w / (lx + ly) for (-w, +w, -w, +w).
  c.w_fl = -4;
  c.w_fr = 4;
  c.w_rl = -4;
  c.w_rr = 4;
  for (int k = 1; k <= 10; ++k) {
    sim.onWheelCmd(c);
    sim.advanceTo(p.start_utime + us(3.5) + k * 100000, out);
  }
  EXPECT_NEAR(sim.robot().body.wz, 0.05 * 4 / 0.4, 1e-3);
  // The upside-down IMU sees the counter-clockwise turn as a negative rate about its own z.
  ASSERT_FALSE(out.imu_packets.empty());
  livox::ParsedPacket pk;
  const auto& b = out.imu_packets.back().bytes;
  ASSERT_EQ(livox::parsePacket(b.data(), b.size(), pk), livox::ParseStatus::kOk);
  EXPECT_NEAR(pk.imu.gyro_z, -0.5, 0.01);
  EXPECT_NEAR(pk.imu.acc_z, -9.80665, 0.1);
}

TEST(SimulatorNode, GivenNonFiniteWheelSpeedsThenTheCommandIsCountedAndTheBaseBrakes) {
  SimulatorParams p = defaults();
  Simulator sim(p, room());
  SimOutputs out;
  wheel_cmd_t c{};
  c.enable = true;
  c.w_fl = c.w_fr = c.w_rl = c.w_rr = 10.0;
  sim.onWheelCmd(c);
  sim.advanceTo(p.start_utime + 300000, out);
  c.w_fr = std::nan("");
  EXPECT_FALSE(sim.onWheelCmd(c));
  sim.advanceTo(p.start_utime + 800000, out);
  EXPECT_EQ(sim.counters().bad_wheel_cmds, 1);
  EXPECT_NEAR(sim.robot().body.vx, 0.0, 1e-3);
  EXPECT_TRUE(std::isfinite(sim.robot().x));
}

TEST(SimulatorNode, GivenTheRobotDrivingIntoAPillarThenGroundTruthFlagsOneCollision) {
  SimulatorParams p = defaults();
  Simulator sim(p, room());  // pillar at x = 3, r = 0.5; robot r = 0.3: contact at x = 2.2
  SimOutputs out;
  wheel_cmd_t c{};
  c.enable = true;
  c.w_fl = c.w_fr = c.w_rl = c.w_rr = 20.0;  // 1 m/s
  for (int k = 0; k <= 30; ++k) {
    sim.onWheelCmd(c);
    sim.advanceTo(p.start_utime + k * 100000, out);
  }
  ASSERT_FALSE(out.ground_truth.empty());
  const auto& g = out.ground_truth.back();
  EXPECT_TRUE(g.collision);
  EXPECT_EQ(g.num_collisions, 1);
  EXPECT_LT(g.min_clearance, 0.0);
  EXPECT_EQ(g.scenario, "room");
  EXPECT_NEAR(g.robot_radius, 0.3, 1e-12);
  // Before contact no ground truth says collision.
  for (const auto& m : out.ground_truth)
    if (m.robot_x < 2.15) {
      EXPECT_FALSE(m.collision) << m.robot_x;
    }
}

TEST(SimulatorNode, GivenMovingObstaclesThenGroundTruthMatchesTheWorldAtFrameTimes) {
  SimulatorParams p = defaults();
  const world::Scenario scen = pedestrians();
  Simulator sim(p, scen);
  world::World ref(scen);
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(2.0), out);
  ASSERT_EQ(out.ground_truth.size(), 101u);
  for (const auto& g : out.ground_truth) {
    ASSERT_EQ(g.num_objects, 3);
    const double t = (g.utime - p.start_utime) * 1e-6;
    for (int i = 0; i < 3; ++i) {
      const auto s = ref.moverState(i, t);
      EXPECT_EQ(g.objects[i].id, s.id);
      EXPECT_DOUBLE_EQ(g.objects[i].x, s.position.x());
      EXPECT_DOUBLE_EQ(g.objects[i].vy, s.velocity.y());
      EXPECT_EQ(g.objects[i].motion, sim_object_t::MOTION_PEDESTRIAN);
      EXPECT_GE(g.objects[i].visible, 0.0);
      EXPECT_LE(g.objects[i].visible, 1.0);
    }
  }
}

TEST(SimulatorNode, GivenAPedestrianOccludedOverTheRunThenGroundTruthVisibilityDropsAndRecovers) {
  SimulatorParams p = defaults();
  Simulator sim(p, pedestrians());
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(60.0), out);
  double min_vis = 1.0, max_vis = 0.0;
  for (const auto& g : out.ground_truth) {
    for (const auto& o : g.objects) {
      min_vis = std::min(min_vis, o.visible);
      max_vis = std::max(max_vis, o.visible);
    }
  }
  // The pedestrians scenario is built to occlude people: some frames hide someone entirely.
  EXPECT_LT(min_vis, 0.2);
  EXPECT_GT(max_vis, 0.8);
}

TEST(SimulatorNode, GivenTheSameInputsThenTwoRunsProduceIdenticalBytes) {
  SimulatorParams p = defaults();
  Simulator a(p, pedestrians()), b(p, pedestrians());
  SimOutputs oa, ob;
  for (int k = 1; k <= 5; ++k) {
    a.advanceTo(p.start_utime + k * 37000, oa);
    b.advanceTo(p.start_utime + k * 37000, ob);
  }
  b.advanceTo(p.start_utime + 185000, ob);  // repeating a time adds nothing
  ASSERT_EQ(oa.point_packets.size(), ob.point_packets.size());
  for (std::size_t i = 0; i < oa.point_packets.size(); ++i) EXPECT_EQ(oa.point_packets[i].bytes, ob.point_packets[i].bytes);
  ASSERT_EQ(oa.imu_packets.size(), ob.imu_packets.size());
  for (std::size_t i = 0; i < oa.imu_packets.size(); ++i) EXPECT_EQ(oa.imu_packets[i].bytes, ob.imu_packets[i].bytes);
}

TEST(SimulatorNode, GivenFrameModeThenEachFrameHoldsAbout4000PointsWithoutPackets) {
  SimulatorParams p = defaults();
  SimOptions o;
  o.make_packets = false;
  o.make_frames = true;
  Simulator sim(p, pedestrians(), o);
  SimOutputs out;
  sim.advanceTo(p.start_utime + us(0.5), out);
  EXPECT_TRUE(out.point_packets.empty());
  ASSERT_EQ(out.frames.size(), 24u);  // frames 0..23 complete; frame 24 still filling
  for (std::size_t i = 0; i < out.frames.size(); ++i) {
    const auto& f = out.frames[i];
    EXPECT_EQ(f.seq, static_cast<int64_t>(i));
    EXPECT_EQ(f.frame_id, "lidar");
    // A frame starts with the first packet at or after i * 20 ms (packets are 480 us apart).
    const int64_t first_packet = (static_cast<int64_t>(i) * 20000 + 479) / 480;
    EXPECT_EQ(f.utime, p.start_utime + first_packet * 480);
    EXPECT_GT(f.num_points, 3800);
    EXPECT_LE(f.num_points, 4128);
    EXPECT_EQ(f.x.size(), static_cast<std::size_t>(f.num_points));
    EXPECT_LT(f.duration_us, 20500);
    for (int k = 1; k < f.num_points; ++k) ASSERT_GE(f.t_offset_ns[k], f.t_offset_ns[k - 1]);
  }
}

TEST(SimulatorNode, GivenFramesInTheBaseFrameThenTheFloorIsAtZeroHeight) {
  SimulatorParams p = defaults();
  p.lidar.range_noise_sigma = 0.0;
  SimOptions o;
  o.make_packets = false;
  o.make_frames = true;
  o.frames_in_base = true;
  Simulator sim(p, room(), o);
  SimOutputs out;
  sim.advanceTo(p.start_utime + 100000, out);
  ASSERT_FALSE(out.frames.empty());
  const auto& f = out.frames[0];
  EXPECT_EQ(f.frame_id, "base");
  // The robot stands at the origin with yaw 0, so base = world: the floor is z = 0 and nothing
  // is above the 2.5 m walls.
  int floor = 0;
  for (int i = 0; i < f.num_points; ++i) {
    EXPECT_GT(f.z[i], -0.01);
    EXPECT_LT(f.z[i], 2.51);
    floor += std::fabs(f.z[i]) < 0.005;
  }
  EXPECT_GT(floor, f.num_points / 2);  // upside down: most rays look at the floor
}
