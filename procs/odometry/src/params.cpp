#include "ucon/odometry/params.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "ucon/config.hpp"

namespace ucon {
namespace odometry {

namespace {
void readVec3(ConfigReader& r, const std::string& key, Eigen::Vector3d& v, double lo, double hi) {
  std::vector<double> xs{v.x(), v.y(), v.z()};
  r.read(key, xs, 3, lo, hi);
  if (xs.size() == 3) v = Eigen::Vector3d(xs[0], xs[1], xs[2]);
}
}  // namespace

void OdometryParams::read(ConfigReader& r) {
  r.read("points_frame", points_frame, {"base", "lidar"});
  r.read("pose_channel", pose_channel, {"ROBOT_POSE", "ODOMETRY_POSE"});
  r.read("health_period_s", health_period_s, 1e-3, 60.0);
  lio::LioParams& p = lio;
  {
    auto s = r.section("imu");
    readVec3(s, "position", p.imu_position, -10.0, 10.0);
    s.read("time_offset_s", p.imu_time_offset_s, -0.1, 0.1);
    s.read("gravity", p.gravity, 9.0, 10.5);
    s.read("gyro_noise", p.noise.gyro_noise, 1e-6, 1.0);
    s.read("acc_noise", p.noise.acc_noise, 1e-6, 10.0);
    s.read("gyro_bias_walk", p.noise.gyro_bias_walk, 1e-9, 1.0);
    s.read("acc_bias_walk", p.noise.acc_bias_walk, 1e-9, 10.0);
    s.read("gap_s", p.imu_gap_s, 1e-3, 1.0);
    s.read("max_gap_s", p.max_imu_gap_s, 1e-3, 60.0);
    s.read("gap_acc_std", p.gap_acc_std, 0.0, 100.0);
    s.read("gap_gyro_std", p.gap_gyro_std, 0.0, 100.0);
  }
  {
    auto s = r.section("init");
    s.read("window_s", p.init_window_s, 0.05, 1.0);
    s.read("max_gyro_std", p.init_max_gyro_std, 1e-6, 10.0);
    s.read("max_acc_std", p.init_max_acc_std, 1e-6, 10.0);
    s.read("max_gravity_error", p.init_max_gravity_error, 1e-6, 5.0);
    readVec3(s, "pose", p.initial_pose, -1e6, 1e6);
    s.read("position_std", p.initial_position_std, 1e-6, 100.0);
    s.read("yaw_std", p.initial_yaw_std, 1e-6, 10.0);
    s.read("velocity_std", p.initial_velocity_std, 1e-6, 10.0);
    s.read("acc_bias_std", p.initial_acc_bias_std, 1e-6, 10.0);
    s.read("gyro_bias_std", p.initial_gyro_bias_std, 1e-6, 1.0);
  }
  {
    auto s = r.section("points");
    s.read("min_range", p.min_range, 0.0, 100.0);
    s.read("max_range", p.max_range, 0.1, 500.0);
    s.read("downsample_voxel", p.downsample_voxel, 0.0, 5.0);
    s.read("min_points", p.min_points, 1, 100000);
    s.read("max_points", p.max_points, 0, 100000);
  }
  {
    auto s = r.section("update");
    s.read("max_iterations", p.max_iterations, 1, 20);
    s.read("knn", p.knn, 3, lio::Neighbours::kMax);
    s.read("max_correspondence", p.max_correspondence, 0.01, 10.0);
    s.read("plane_threshold", p.plane_threshold, 1e-3, 1.0);
    s.read("point_std", p.point_std, 1e-4, 1.0);
    s.read("robust_scale", p.robust_scale, 1e-3, 10.0);
    s.read("outlier_distance", p.outlier_distance, 1e-3, 10.0);
    s.read("converged_rotation", p.converged_rotation, 1e-9, 0.1);
    s.read("converged_translation", p.converged_translation, 1e-9, 1.0);
    s.read("research_translation", p.research_translation, 1e-6, 10.0);
    s.read("research_rotation", p.research_rotation, 1e-6, 1.0);
    s.read("min_matched_ratio", p.min_matched_ratio, 0.0, 1.0);
  }
  {
    auto s = r.section("map");
    s.read("voxel_size", p.map.voxel_size, 0.05, 10.0);
    s.read("max_points_per_voxel", p.map.max_points_per_voxel, 1, 64);
    s.read("min_point_spacing", p.map.min_point_spacing, 0.0, 5.0);
    s.read("max_voxels", p.map.max_voxels, int64_t{1}, int64_t{100000000});
    s.read("radius", p.map.radius, 1.0, 10000.0);
    int nbh = static_cast<int>(p.map.neighbourhood);
    s.read("neighbourhood", nbh, 6, 26);
    if (nbh != 6 && nbh != 18 && nbh != 26) s.fail("neighbourhood", "must be 6, 18 or 26");
    p.map.neighbourhood = static_cast<lio::Neighbourhood>(nbh);
    s.read("trim_every_m", p.map_trim_every_m, 0.01, 1000.0);
    s.read("insert_max_residual", p.map_insert_max_residual, 1e-3, 10.0);
    s.read("carve_every", p.map_carve_every, 0, 1000);
    s.read("carve_radius", p.map.carve_radius, 0.5, 100.0);
    s.read("carve_bin_deg", p.map.carve_bin_deg, 0.1, 30.0);
    s.read("carve_margin", p.map.carve_margin, 0.0, 10.0);
    s.read("carve_misses", p.map.carve_misses, 1, 1000);
  }
  {
    auto s = r.section("ground_prior");
    s.read("enabled", p.ground_prior);
    s.read("height_std", p.ground_height_std, 1e-4, 10.0);
    s.read("tilt_std", p.ground_tilt_std, 1e-4, 1.0);
  }
  {
    auto s = r.section("output");
    s.read("imu_only_timeout_s", p.imu_only_timeout_s, 0.01, 10.0);
    s.read("max_pending_frames", p.max_pending_frames, 1, 1000);
  }
  const std::string bad = p.validate();
  if (!bad.empty()) r.fail(bad.substr(0, bad.find(':')), bad.substr(bad.find(':') + 2));
}

std::string OdometryParams::validate() const {
  if (points_frame != "base" && points_frame != "lidar") return "points_frame: must be base or lidar";
  if (!(health_period_s > 0.0)) return "health_period_s: must be > 0";
  if (pose_channel != "ROBOT_POSE" && pose_channel != "ODOMETRY_POSE")
    return "pose_channel: must be ROBOT_POSE or ODOMETRY_POSE";
  return lio.validate();
}

std::optional<std::string> withInitialPose(const std::string& yaml, const Eigen::Vector3d& pose) {
  std::istringstream in(yaml);
  std::string out, line;
  bool in_init = false, done = false;
  while (std::getline(in, line)) {
    const std::size_t indent = line.find_first_not_of(' ');
    const bool top = indent == 0 && !line.empty() && line[0] != '#';
    if (top) in_init = line.rfind("init:", 0) == 0;
    if (in_init && !done && indent != std::string::npos && indent > 0 && line.compare(indent, 5, "pose:") == 0) {
      const std::size_t open = line.find('['), close = line.find(']');
      if (open == std::string::npos || close == std::string::npos || close < open) return std::nullopt;
      char buf[128];
      std::snprintf(buf, sizeof(buf), "[%.17g, %.17g, %.17g]", pose.x(), pose.y(), pose.z());
      line = line.substr(0, open) + buf + line.substr(close + 1);
      done = true;
    }
    out += line + "\n";
  }
  if (!done) return std::nullopt;
  return out;
}

}  // namespace odometry
}  // namespace ucon
