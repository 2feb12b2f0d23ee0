#pragma once
/// @file point_index.hpp
/// Nearest-neighbour index over a point set (a PCL KD-tree behind a PCL-free interface), and
/// the PCL stages that work on it: voxel down-sampling and Euclidean clustering.

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace ucon {
namespace perception {

using Points = std::vector<Eigen::Vector3f>;

/// KD-tree over a copy of a point set. Build once per set, query often.
class PointIndex {
 public:
  PointIndex();
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  /// (Re)builds the index over `points` (finite points only are expected).
  void build(const Points& points);
  /// Number of indexed points.
  int size() const;
  /// Index of the nearest point to `q` and its squared distance [m^2]; -1 if empty.
  int nearest(const Eigen::Vector3f& q, float* dist2) const;
  /// Groups of point indices within `tolerance` [m] of each other (PCL Euclidean cluster
  /// extraction), groups of size outside [min_points, max_points] dropped. Each group sorted.
  std::vector<std::vector<int>> clusters(double tolerance, int min_points, int max_points) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Voxel-grid down-sampling (PCL VoxelGrid, one centroid per occupied voxel of edge
/// `voxel` [m]); deterministic order.
Points voxelDownsample(const Points& points, double voxel);

}  // namespace perception
}  // namespace ucon
