#pragma once
/// @file proximity_index.hpp
/// Uniform grid over a point set for the motion test's question "is any point within r of
/// q?": built in linear time (a counting sort into 0.25 m cells; the motion test builds one
/// per history chunk, ten a second), a query visits the cells the ball touches and stops at
/// the first point inside. The answers are exactly those of a nearest-neighbour distance
/// compared with r (the KD-tree it replaced gave the same, byte for byte in the node's output).

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
