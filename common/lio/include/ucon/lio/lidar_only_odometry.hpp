#pragma once
/// @file lidar_only_odometry.hpp
/// The LiDAR-only baseline (KISS-ICP, Vizzo et al. 2023, with the odometry's own map and
/// planes): a constant-velocity prediction of the frame's motion, points de-skewed with that
/// velocity, registration to the same voxel map with the robust point-to-plane core
/// (registration.hpp) and KISS-ICP's adaptive threshold: the correspondence distance is
/// three times the rms deviation of the registered pose from the prediction over past
/// frames, the kernel scale a third of it. No IMU: it starts level at the initial pose.

#include <Eigen/Geometry>

#include <cstdint>

#include "ucon/lio/lio_odometry.hpp"
#include "ucon/lio/registration.hpp"
#include "ucon/lio/voxel_map.hpp"

namespace ucon {
namespace lio {

class LidarOnlyOdometry {
 public:
  /// Uses the range, downsampling, plane, kernel and map settings of `params`; starts at
  /// params.initial_pose (base x, y, yaw; level, z = 0).
  explicit LidarOnlyOdometry(const LioParams& params);

  struct Result {
    int64_t t_ns = 0;                                      ///< frame end
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  ///< base pose (world <- points frame)
    bool registered = false;                               ///< false: the prediction was kept
    int iterations = 0;
    int correspondences = 0;
  };

  /// Registers one frame (points frame, times ascending). Frames that do not come after
  /// the previous one are ignored (registered = false, last pose returned).
  Result addFrame(const PointFrame& frame);

  const VoxelMap& map() const { return map_; }

 private:
  LioParams p_;
  VoxelMap map_;
  Eigen::Isometry3d T_last_ = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 1> velocity_ = Eigen::Matrix<double, 6, 1>::Zero();  // body (w, v) [rad/s, m/s]
  int64_t t_last_ = 0;
  bool started_ = false;
  double dev2_sum_ = 0.0;
  int dev_n_ = 0;
};

}  // namespace lio
}  // namespace ucon
