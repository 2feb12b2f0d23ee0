#pragma once
/// @file registration.hpp
/// The x-y displacement of an object between two views of it, by aligning their points.
///
/// Differencing two centres measures the object's motion plus the change of what the sensor
/// saw of it: a neighbour merging into the cluster, a corner hidden by an occluder, a sparse
/// scan. The surface that both views share moves with the object; the parts only one view has
/// do not match anything in the other. A translation-only alignment (trimmed ICP in x-y:
/// nearest neighbours, pairs beyond a shrinking gate left out) measures the shared surface's
/// motion.

#include <Eigen/Core>

#include "ucon/perception/point_index.hpp"

namespace ucon {
namespace perception {

struct RegistrationParams {
  double initial_gate = 0.5;  ///< pair distance gate of the first iteration [m]
  double final_gate = 0.12;   ///< ... shrunk geometrically to this by the last iteration [m]
  int iterations = 6;         ///< >= 1
  double min_inliers = 0.5;   ///< share of `from`'s points that must pair up at the last iteration
  int min_points = 5;         ///< fewer points in either view: no registration
};

/// Translation d (x-y) that moves `from` onto `to`, starting from `guess`. Returns false (and
/// leaves *d alone) when either view has fewer than min_points points, when too few points pair
/// up at the last iteration, or when `guess` is not finite; a non-finite point pairs with
/// nothing. O(iterations * |from| * |to|): callers thin the views.
bool registerTranslation(const Points& from, const Points& to, const Eigen::Vector2d& guess,
                         const RegistrationParams& params, Eigen::Vector2d* d);

}  // namespace perception
}  // namespace ucon
