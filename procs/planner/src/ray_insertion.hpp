#pragma once
/// @file ray_insertion.hpp
/// Ray insertion of static points into the planner map's 3-D tree: OctoMap's own discretised
/// insertion (all heights), or the same update restricted to the robot's height band (rays
/// traced only while they can change the band), optionally on two threads. Private to
/// ucon_planner_map.

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "leaf_cache.hpp"
#include "ucon/planner/esdf_map.hpp"

namespace ucon::planner {

/// The keys OctoMap's OcTree::computeRayKeys(origin, end, ray) would put into `ray`, in the
/// same order, handed to `visit(key)` one by one instead of being stored: the same 3-D DDA
/// (Amanatides & Woo) with the same arithmetic, so the same cells (tested against
/// computeRayKeys on random rays). False, visiting nothing, when an end lies outside the tree.
template <class Visit>
bool traceRayKeys(const octomap::OcTree& t, const octomap::point3d& origin, const octomap::point3d& end,
                  Visit&& visit) {
  octomap::OcTreeKey key_origin, key_end;
  if (!t.coordToKeyChecked(origin, key_origin) || !t.coordToKeyChecked(end, key_end)) return false;
  if (key_origin == key_end) return true;
  visit(key_origin);
  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;
  const double resolution = t.getResolution();
  int step[3];
  double t_max[3], t_delta[3];
  octomap::OcTreeKey current = key_origin;
  for (unsigned i = 0; i < 3; ++i) {
    step[i] = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    if (step[i] != 0) {
      double border = t.keyToCoord(current[i]);
      border += float(step[i] * resolution * 0.5);
      t_max[i] = (border - origin(i)) / direction(i);
      t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  while (true) {
    unsigned dim;
    if (t_max[0] < t_max[1]) {
      dim = t_max[0] < t_max[2] ? 0 : 2;
    } else {
      dim = t_max[1] < t_max[2] ? 1 : 2;
    }
    current[dim] = octomap::key_type(current[dim] + step[dim]);
    t_max[dim] += t_delta[dim];
    if (current == key_end) return true;
    if (std::min(std::min(t_max[0], t_max[1]), t_max[2]) > length) return true;
    visit(current);
  }
}

class InsertHelper;

/// Inserts frames into a LeafCache's tree. Holds the insertion's scratch buffers (reused from
/// frame to frame) and, with two threads, the helper thread.
class RayInsertion {
 public:
  explicit RayInsertion(const MapParams& params);
  ~RayInsertion();
  RayInsertion(const RayInsertion&) = delete;
  RayInsertion& operator=(const RayInsertion&) = delete;

  /// Ray-inserts `points` [m] (world frame) from `origin` (finite) into `leaves`, rays cut at
  /// `range` [m] (> 0): every cell along a ray becomes freer, end points more occupied.
  /// Non-finite points are skipped and added to `*skipped`.
  InsertStatus insert(LeafCache& leaves, const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3f>& points,
                      double range, int64_t* skipped);
  /// CPU seconds the helper thread has used (0 with one thread).
  double helperCpuSeconds() const;

 private:
  /// OctoMap's discretised insertPointCloud (all heights).
  InsertStatus insertAllHeights(LeafCache& leaves, const octomap::point3d& origin,
                                const std::vector<Eigen::Vector3f>& points, double range, int64_t* skipped);
  /// The same update restricted to the height band (see the .cpp).
  InsertStatus insertBand(LeafCache& leaves, const octomap::point3d& origin,
                          const std::vector<Eigen::Vector3f>& points, double range, int64_t* skipped);

  MapParams params_;
  std::vector<uint64_t> endpoints_, free_outside_, occupied_;  // packed keys
  std::vector<uint64_t> endpoints_outside_;  // endpoint leaves outside the dedup grid
  std::vector<octomap::point3d> ray_ends_;   // where each endpoint's ray is traced to
  std::vector<uint64_t> seen_;  // per-cell dedup bits (endpoints; then cells updated, or occupied: to be)
  // The helper's share of a two-thread insertion: its own dedup bits, the cells new to its
  // rays in order, and its cells outside the grid.
  std::unique_ptr<InsertHelper> helper_;
  std::vector<uint64_t> helper_seen_;
  std::vector<octomap::OcTreeKey> helper_fresh_;
  std::vector<uint64_t> helper_free_outside_;
};

}  // namespace ucon::planner
