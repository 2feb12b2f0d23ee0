#pragma once
/// @file distance_field.hpp
/// The optimiser's view of the static map: a 2-D distance field Ξ(p) with its gradient.
/// The planner implements it over its ESDF; tests implement it analytically.

#include <Eigen/Core>

namespace ucon::trajopt {

class DistanceField2D {
 public:
  virtual ~DistanceField2D() = default;
  /// Distance [m] from (x, y) [m] to the nearest static obstacle (may be capped far from
  /// obstacles, may be <= 0 inside one). When `grad` is not null, writes dΞ/dp [m/m]
  /// (zero where the field is flat or capped). Must be deterministic and cheap: the
  /// optimiser calls it at every sample of every evaluation.
  virtual double distance(double x, double y, Eigen::Vector2d* grad) const = 0;
};

}  // namespace ucon::trajopt
