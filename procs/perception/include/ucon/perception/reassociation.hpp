#pragma once
/// @file reassociation.hpp
/// Point-level historical re-association (paper Sec. III-B and the appendix algorithm).

#include <vector>

#include <Eigen/Core>

#include "ucon/perception/association.hpp"
#include "ucon/perception/params.hpp"
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

/// A track left unmatched by object-level association, as point-level recovery sees it.
struct LostTrack {
  HistoricalObject history;  ///< T_c, v_c, tau
  TrackView view;            ///< its prediction (box.center) and heading, for the gates
};

/// What point-level recovery gives the frame.
struct Recovery {
  /// Per lost track (in the given order): the frame points that measure it now, empty when it
  /// is not recovered.
  std::vector<std::vector<int>> points;
  /// Per frame point: some lost track's re-association claimed it (whether or not that track
  /// was then recovered); points measured by an object-level match stay unclaimed.
  std::vector<char> claimed;
};

/// Stage 4 of the pipeline: the appendix algorithm over every point of the frame (`index` is
/// built over `points`), and its conflicts resolved:
///  - a point measured by an object-level match (`matched`: the points of each match) stays
///    with it, and the lost track keeps the rest of what it re-associated;
///  - fewer than 2 points left, a centre farther than max_shift from the track's prediction
///    (typically the occluder in front of a hidden object), or a view-corrected centre outside
///    the track's cross-heading gate (passesCrossGate: a neighbour on the next line) is not a
///    recovery.
Recovery recoverLostTracks(const std::vector<LostTrack>& lost, const Points& points, const ProximityIndex& index,
                           const std::vector<const std::vector<int>*>& matched, const Eigen::Vector2d& sensor_xy,
                           const PerceptionParams& params);

/// Whether a cluster (`indices` into the frame) lies mostly (at least half) on points that
/// recovery claimed: it is the recovered objects', not a new one.
bool mostlyClaimed(const std::vector<int>& indices, const std::vector<char>& claimed);

}  // namespace perception
}  // namespace ucon
