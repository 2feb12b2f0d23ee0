#pragma once
/// @file params.hpp
/// Parameters of ucon-odometry. deploy/config/odometry.yaml maps one-to-one onto them; the
/// in-class defaults (here and in ucon::lio::LioParams) equal the shipped file.

#include <optional>
#include <string>

#include "ucon/lio/lio_odometry.hpp"

namespace ucon {
class ConfigReader;

namespace odometry {

struct OdometryParams {
  std::string points_frame = "base";  ///< frame_id expected on LIDAR_POINTS and LIDAR_IMU (the driver's extrinsic applied)
  /// Where poses go: ROBOT_POSE (the robot's pose) or ODOMETRY_POSE (beside another pose
  /// source, e.g. the simulator's ground truth, for comparison).
  std::string pose_channel = "ROBOT_POSE";
  double health_period_s = 1.0;       ///< ODOMETRY_HEALTH period [s] (wall time), (0, 60]
  lio::LioParams lio;                 ///< sections imu, init, points, update, map, ground_prior, output

  /// Reads every key (all required); errors name the dotted key.
  void read(ConfigReader& r);
  /// Empty when consistent, else the bad key and why.
  std::string validate() const;
};

/// `yaml` (odometry.yaml text) with the value of init.pose replaced by (x, y, yaw) [m, m,
/// rad], comments and layout kept; nullopt if the file has no `pose:` line in its `init:`
/// section. How a run records the start pose it was given (the logger stores the text).
std::optional<std::string> withInitialPose(const std::string& yaml, const Eigen::Vector3d& pose);

}  // namespace odometry
}  // namespace ucon
