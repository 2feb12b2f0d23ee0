#pragma once
/// @file synthetic_run.hpp
/// Test data for the odometry with an exactly known motion: a planar base trajectory given
/// as a function of time, IMU samples derived from it (central differences of the pose,
/// lever arm to the IMU included; optional noise and constant biases), and LiDAR frames ray
/// cast into a ucon::world::World along the simulator's Mid-360 pattern, the sensor mounted
/// upside down 0.5 m above the base, points published in the base frame with per-point time.
#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <vector>

#include "ucon/lio/lio_odometry.hpp"
#include "ucon/lio/so3.hpp"
#include "ucon/simulator/lidar_emulator.hpp"
#include "ucon/world/rng.hpp"
#include "ucon/world/world.hpp"

namespace ucon {
namespace test {

/// Base pose (x, y, yaw) at time t [s].
using PlanarMotion = std::function<Eigen::Vector3d(double t)>;

/// Standstill until t0, then a smooth drive (the base is omnidirectional): speed ramps to
/// `speed` over ~1 s along a weaving path while the heading swings by up to +-`turn` rad.
inline PlanarMotion curvyDrive(double t0, double speed, double turn, Eigen::Vector3d start = Eigen::Vector3d::Zero()) {
  return [=](double t) {
    if (t <= t0) return start;
    const double s = t - t0;
    // Distance along the path: speed * (s - (1 - exp(-2 s)) / 2): zero velocity at s = 0.
    const double dist = speed * (s - 0.5 * (1.0 - std::exp(-2.0 * s)));
    const double yaw = start.z() + turn * std::sin(0.35 * dist) * (1.0 - std::exp(-2.0 * s));
    // x along the start heading, y a sinusoid of the distance.
    const double c = std::cos(start.z()), sn = std::sin(start.z());
    const double lx = dist, ly = 0.6 * (1.0 - std::cos(0.3 * dist));
    return Eigen::Vector3d(start.x() + c * lx - sn * ly, start.y() + sn * lx + c * ly, yaw);
  };
}

struct SyntheticOptions {
  double imu_rate_hz = 200.0;
  double frame_rate_hz = 50.0;
  double point_rate = 200000.0;
  double gyro_noise_sigma = 0.0;   ///< per sample [rad/s]
  double acc_noise_sigma = 0.0;    ///< per sample [m/s^2]
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d acc_bias = Eigen::Vector3d::Zero();
  double range_noise_sigma = 0.0;
  Eigen::Vector3d imu_position = Eigen::Vector3d(0.011, -0.023, 0.544);  ///< in the base frame
  uint64_t seed = 7;
};

/// Generates IMU samples and frames of a motion in a world.
class SyntheticRun {
 public:
  SyntheticRun(world::World world, PlanarMotion motion, SyntheticOptions o = {})
      : world_(std::move(world)), motion_(std::move(motion)), o_(o), lidar_(lidarParams(o)), rng_(o.seed) {}

  static simulator::LidarParams lidarParams(const SyntheticOptions& o) {
    simulator::LidarParams p;
    p.point_rate = o.point_rate;
    p.range_noise_sigma = o.range_noise_sigma;
    return p;
  }

  /// Base pose as an isometry (z = 0, level).
  Eigen::Isometry3d basePose(double t) const {
    const Eigen::Vector3d q = motion_(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = lio::rotationFromRpy(0, 0, q.z());
    T.translation() = Eigen::Vector3d(q.x(), q.y(), 0.0);
    return T;
  }

  /// IMU sample at t [s] (base axes, SI), from central differences of the IMU position.
  lio::ImuSample imu(double t) {
    const double h = 1e-3;
    auto pos = [&](double tt) { return (basePose(tt) * o_.imu_position).eval(); };
    const Eigen::Vector3d a = (pos(t + h) - 2.0 * pos(t) + pos(t - h)) / (h * h);
    const double wz = wrap(motion_(t + 1e-5).z() - motion_(t - 1e-5).z()) / 2e-5;
    const Eigen::Matrix3d R = basePose(t).linear();
    lio::ImuSample s;
    s.t_ns = static_cast<int64_t>(std::llround(t * 1e9));
    s.gyro = Eigen::Vector3d(0, 0, wz) + o_.gyro_bias;
    s.acc = R.transpose() * (a + Eigen::Vector3d(0, 0, 9.80665)) + o_.acc_bias;
    for (int i = 0; i < 3; ++i) {
      s.gyro[i] += o_.gyro_noise_sigma * rng_.normal();
      s.acc[i] += o_.acc_noise_sigma * rng_.normal();
    }
    return s;
  }

  /// The LiDAR frame starting at t0 [s] (points in the base frame).
  lio::PointFrame frame(double t0) {
    lio::PointFrame f;
    const double spacing = 1.0 / o_.point_rate;
    const int64_t k0 = static_cast<int64_t>(std::llround(t0 / spacing));
    const int n = static_cast<int>(std::llround(o_.point_rate / o_.frame_rate_hz));
    f.t0_ns = static_cast<int64_t>(std::llround(k0 * spacing * 1e9));
    for (int i = 0; i < n; ++i) {
      const double t = (k0 + i) * spacing;
      const Eigen::Isometry3d T_ws = basePose(t) * lidar_.mount();
      world_.setTime(t);
      const Eigen::Vector3d ds = lidar_.direction(static_cast<uint64_t>(k0 + i));
      const world::RayHit hit = world_.castRay(T_ws.translation(), T_ws.linear() * ds, 40.0);
      const double noise = o_.range_noise_sigma * rng_.normal();
      if (hit.kind == world::HitKind::kNone) continue;
      const Eigen::Vector3d p_s = ds * (hit.range + noise);
      f.points.push_back((lidar_.mount() * p_s).cast<float>());
      f.dt_ns.push_back(static_cast<int64_t>(std::llround(t * 1e9)) - f.t0_ns);
    }
    return f;
  }

  /// Runs the odometry from 0 to t_end [s]: IMU samples and frames in time order (a frame is
  /// given once its last point is measured). `on_pose` sees every pose estimate.
  void run(lio::LioOdometry& odo, double t_end, const std::function<void(const lio::PoseEstimate&)>& on_pose,
           std::vector<lio::FrameReport>* reports, double frame_from = 0.0) {
    const double dti = 1.0 / o_.imu_rate_hz, dtf = 1.0 / o_.frame_rate_hz;
    int i = 0, k = static_cast<int>(std::llround(frame_from / dtf));
    while (true) {
      const double ti = i * dti, tf_end = (k + 1) * dtf;
      if (ti > t_end && tf_end > t_end) break;
      if (tf_end <= ti) {
        odo.addFrame(frame(k * dtf), reports);
        ++k;
      } else {
        const auto pose = odo.addImu(imu(ti));
        if (pose && on_pose) on_pose(*pose);
        odo.runDueFrames(reports);
        ++i;
      }
    }
  }

  world::World& world() { return world_; }

 private:
  static double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }
  world::World world_;
  PlanarMotion motion_;
  SyntheticOptions o_;
  simulator::LidarEmulator lidar_;
  world::Rng rng_;
};

/// A 14 x 10 m walled room with pillars and boxes (every direction constrained).
inline world::Scenario roomScenario() {
  world::Scenario s;
  s.name = "odometry-room";
  s.bounds = {-4.0, 10.0, -5.0, 5.0};
  s.robot.goals = {Eigen::Vector2d(8.0, 0.0)};
  using world::makeWall;
  s.statics.push_back(makeWall({-4.0, 5.0}, {10.0, 5.0}, 0.2, 2.5));
  s.statics.push_back(makeWall({-4.0, -5.0}, {10.0, -5.0}, 0.2, 2.5));
  s.statics.push_back(makeWall({-4.0, -5.0}, {-4.0, 5.0}, 0.2, 2.5));
  s.statics.push_back(makeWall({10.0, -5.0}, {10.0, 5.0}, 0.2, 2.5));
  world::StaticObstacle c;
  c.kind = world::ShapeKind::kCylinder;
  for (const auto& xy : {Eigen::Vector2d(2.0, 2.5), Eigen::Vector2d(5.0, -2.0), Eigen::Vector2d(7.5, 3.0)}) {
    c.center = xy;
    c.radius = 0.35;
    c.height = 2.2;
    s.statics.push_back(c);
  }
  world::StaticObstacle b;
  b.kind = world::ShapeKind::kBox;
  b.center = Eigen::Vector2d(3.5, -3.0);
  b.half_size = Eigen::Vector2d(0.6, 0.4);
  b.yaw = 0.3;
  b.height = 1.2;
  s.statics.push_back(b);
  b.center = Eigen::Vector2d(-1.5, 3.2);
  b.yaw = -0.5;
  b.height = 1.6;
  s.statics.push_back(b);
  return s;
}

}  // namespace test
}  // namespace ucon
