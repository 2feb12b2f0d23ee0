#pragma once
/// @file proximity_index.hpp
/// Uniform grid over a point set for the motion test's question "is any point within r of
/// q?" and re-association's "which point is nearest to q, if closer than d0?": built in linear
/// time (a counting sort into cells; the motion test builds one per history chunk, ten a
/// second, re-association one per frame with a lost track), a query visits the cells the ball
/// touches. The answers are exactly those of a nearest-neighbour search compared with the
/// radius (the KD-trees it replaced gave the same, byte for byte in the node's output).

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

  /// (Re)builds the index over a copy of `points` (non-finite points are left out), in cells
  /// of `cell` metres (doubled until the grid has at most 2^22 cells; a cell about the query
  /// radius keeps queries to a few cells).
  void build(const std::vector<Eigen::Vector3f>& points, double cell = 0.25);
  /// Number of indexed points.
  int size() const;
  /// True when some indexed point p has |p - q|^2 <= max_dist2 [m^2]; false for a non-finite
  /// q or bound, a negative bound, or an empty index.
  bool anyWithin(const Eigen::Vector3f& q, float max_dist2) const;
  /// The point nearest to q among those with |p - q|^2 < max_dist2 (strictly): its index in
  /// the vector given to build(), the lowest such index on a tie, and its squared distance in
  /// `dist2` (may be null). -1 when there is none (also for a non-finite q or bound).
  int nearestWithin(const Eigen::Vector3f& q, float max_dist2, float* dist2) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace perception
}  // namespace ucon
