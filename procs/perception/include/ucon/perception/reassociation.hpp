#pragma once
/// @file reassociation.hpp
/// Point-level historical re-association (paper Sec. III-B and the appendix algorithm).

#include <vector>

#include <Eigen/Core>

#include "ucon/perception/point_index.hpp"
#include "ucon/perception/proximity_index.hpp"

namespace ucon {
namespace perception {

/// One object left unmatched by the object-level association: its historical points T_c.
struct HistoricalObject {
  Points points;                                      ///< T_c, world frame [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero(); ///< predicted velocity v_c [m/s]
  double tau = 0.0;                                   ///< time since T_c was observed [s], >= 0
};

/// For each object, the indices (into the point set P that `index` was built over) of the
/// points it re-associates, sorted and without repeats; empty when it fails.
///
/// Appendix algorithm: every p in T_c is displaced by v_c tau and its nearest point q in P
/// is found; p matches when |p + v_c tau - q| < d0, and q joins P_c. The object is
/// recovered when the number of matches n exceeds gamma N_c (N_c = |T_c|). A point of P
/// recovered by several objects stays with the first of them (objects in the given order).
/// `index` is built over P; cells of about d0 keep each query to a few cells.
std::vector<std::vector<int>> reassociate(const std::vector<HistoricalObject>& objects,
                                          const ProximityIndex& index, double d0, double gamma);

}  // namespace perception
}  // namespace ucon
