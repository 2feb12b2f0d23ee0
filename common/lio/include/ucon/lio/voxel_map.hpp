#pragma once
/// @file voxel_map.hpp
/// The local map: an incremental voxel hash (Faster-LIO's iVox, Bai et al. 2022). World points
/// are kept in cubic voxels of `voxel_size`, at most `max_points_per_voxel` each and no two
/// closer than `min_point_spacing`; a nearest-neighbour query looks at the query's voxel and
/// its face neighbours (or all 26). Memory is bounded two ways: voxels farther than `radius`
/// from the robot are dropped (removeFar), and beyond `max_voxels` the least recently
/// updated voxel goes (an LRU list, as iVox). carve() removes what the sensor now sees
/// through: the trace of a person who walked past stays in no map for long.
///
/// Deterministic: results depend only on the sequence of calls (ties between equally distant
/// points go to the one stored first), never on hash-table iteration order.

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace ucon {
namespace lio {

/// Which voxels a query searches besides its own.
enum class Neighbourhood : uint8_t {
  kFaces = 6,       ///< the 6 face neighbours (iVox NEARBY6)
  kFacesEdges = 18, ///< faces and edges (NEARBY18)
  kAll = 26,        ///< the full 3x3x3 block (NEARBY26)
};

struct VoxelMapParams {
  double voxel_size = 0.5;          ///< voxel edge [m], > 0
  int max_points_per_voxel = 20;    ///< points kept per voxel, [1, 64]
  double min_point_spacing = 0.1;   ///< a new point closer than this to a kept one is dropped [m], >= 0
  int64_t max_voxels = 200000;      ///< LRU bound on the number of voxels, >= 1
  double radius = 60.0;             ///< removeFar() drops voxels whose centre is farther [m], > 0
  Neighbourhood neighbourhood = Neighbourhood::kFaces;
  /// carve(): voxels up to this far from the sensor are tested [m], > 0.
  double carve_radius = 20.0;
  /// carve(): angular bin of the range image [deg], > 0.
  double carve_bin_deg = 2.0;
  /// carve(): a voxel is seen through when every return of its bin is this much (plus the
  /// bin's width at the centroid's range) farther than its points' centroid [m], >= 0.
  double carve_margin = 0.5;
  /// carve(): a voxel seen through by this many carves without a point added to it (or
  /// falling into it) in between is dropped, >= 1.
  int carve_misses = 3;
};

/// Result of one k-nearest-neighbour query (squared distances ascending).
struct Neighbours {
  static constexpr int kMax = 8;
  int count = 0;
  Eigen::Vector3f points[kMax];
  float dist2[kMax];
};

class VoxelMap {
 public:
  explicit VoxelMap(const VoxelMapParams& params);
  ~VoxelMap();
  VoxelMap(VoxelMap&&) noexcept;
  VoxelMap& operator=(VoxelMap&&) noexcept;
  VoxelMap(const VoxelMap&) = delete;
  VoxelMap& operator=(const VoxelMap&) = delete;

  /// Adds world points [m] (non-finite ones are skipped). Returns how many were kept.
  std::size_t insert(const std::vector<Eigen::Vector3f>& points);
  /// Adds one point; true if kept.
  bool insert(const Eigen::Vector3f& point);

  /// Up to `k` (<= Neighbours::kMax) nearest stored points within `max_distance` [m] of `q`
  /// among the searched voxels. Returns the count.
  int nearest(const Eigen::Vector3f& q, int k, float max_distance, Neighbours* out) const;

  /// Free-space carving (the visibility test of removal methods such as Removert, Kim & Kim
  /// 2020, in its simplest form). `points` is one scan in the frame of a sensor at `origin`
  /// with world-from-sensor rotation `R`. The scan becomes a range image of
  /// carve_bin_deg bins holding each bin's nearest return; every voxel within carve_radius
  /// (and 3 m above or below the sensor) whose centroid lies in a bin with a return, all of
  /// whose returns are more than carve_margin plus the bin's width at that range beyond the
  /// centroid, is seen through: a miss.
  /// A voxel with carve_misses misses and no insert() touching it in between is dropped.
  /// Returns the number of voxels dropped.
  std::size_t carve(const Eigen::Vector3d& origin, const Eigen::Matrix3d& R,
                    const std::vector<Eigen::Vector3f>& points);
  /// Drops every voxel whose centre is farther than params.radius from `center` [m].
  /// Returns the number of voxels dropped.
  std::size_t removeFar(const Eigen::Vector3d& center);

  void clear();
  std::size_t numVoxels() const;
  std::size_t numPoints() const;
  bool empty() const { return numPoints() == 0; }
  const VoxelMapParams& params() const { return params_; }

  /// Every stored point (voxels in LRU order, most recent first); for tools and tests.
  std::vector<Eigen::Vector3f> points() const;

 private:
  struct Impl;
  VoxelMapParams params_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lio
}  // namespace ucon
