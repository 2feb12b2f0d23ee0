#pragma once
/// @file registration.hpp
/// Scan-to-map registration without an IMU: robust point-to-plane Gauss-Newton over SE(3)
/// against a VoxelMap. The registration core of the LiDAR-only baseline (KISS-ICP style,
/// Vizzo et al. 2023, with planes instead of points) and of the real-scan test.
///
/// Cost: sum_i rho(r_i) with r_i = n_i . (R p_i + t) + d_i and the Cauchy kernel
/// rho(r) = c^2/2 log(1 + r^2/c^2), minimised by iteratively reweighted Gauss-Newton
/// (weights w_i = 1 / (1 + r_i^2 / c^2)); correspondences (k nearest map points, plane fit)
/// are searched again at every iteration.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

#include "ucon/lio/voxel_map.hpp"

namespace ucon {
namespace lio {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

struct RegistrationParams {
  int max_iterations = 20;              ///< Gauss-Newton iterations, >= 1
  int knn = 5;                          ///< map points per plane, [3, 8]
  double max_correspondence = 1.0;      ///< farthest neighbour used [m], > 0
  double plane_threshold = 0.1;         ///< plane fit rejected if a point is farther [m], > 0
  double robust_scale = 0.1;            ///< Cauchy kernel scale c [m], > 0
  double converged_rotation = 1e-5;     ///< stop when the step is below [rad]
  double converged_translation = 1e-4;  ///< ... and below [m]
};

struct RegistrationResult {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  ///< map <- scan
  int iterations = 0;
  int correspondences = 0;    ///< points with a plane at the last iteration
  double rms = 0.0;           ///< rms residual of those [m]
  Matrix6 information = Matrix6::Zero();  ///< sum w J^T J at the end, over (dtheta, dt)
  bool converged = false;
};

/// Aligns `points` (scan frame) to `map`, starting at `initial`.
RegistrationResult registerPointToPlane(const VoxelMap& map, const std::vector<Eigen::Vector3f>& points,
                                        const Eigen::Isometry3d& initial, const RegistrationParams& params);

/// Voxel-grid downsampling: one point per cubic cell of `voxel` [m] — the first one met in
/// `points` order, so the result keeps the input's order. voxel <= 0 copies.
std::vector<Eigen::Vector3f> voxelDownsample(const std::vector<Eigen::Vector3f>& points, double voxel);
/// The same, returning indices into `points`.
std::vector<int> voxelDownsampleIndices(const std::vector<Eigen::Vector3f>& points, double voxel);

}  // namespace lio
}  // namespace ucon
