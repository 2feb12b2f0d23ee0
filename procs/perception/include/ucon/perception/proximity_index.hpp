#pragma once
/// @file proximity_index.hpp
/// KD-tree (nanoflann) over a point set for the motion test's question "is any point within
/// r of q?": the search stops at the first point inside the ball instead of finding the
/// nearest one, and builds and queries without per-call allocation. The answers are exactly
/// those of a nearest-neighbour distance compared with r.

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace ucon {
namespace perception {

class ProximityIndex {
 public:
  ProximityIndex();
  ~ProximityIndex();
  ProximityIndex(ProximityIndex&&) noexcept;
  ProximityIndex& operator=(ProximityIndex&&) noexcept;
  ProximityIndex(const ProximityIndex&) = delete;
  ProximityIndex& operator=(const ProximityIndex&) = delete;

  /// (Re)builds the index over a copy of `points` (non-finite points are left out).
  void build(const std::vector<Eigen::Vector3f>& points);
  /// Number of indexed points.
  int size() const;
  /// True when some indexed point p has |p - q|^2 <= max_dist2 [m^2]; false for a non-finite
  /// q or bound, a negative bound, or an empty index.
  bool anyWithin(const Eigen::Vector3f& q, float max_dist2) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace perception
}  // namespace ucon
