#pragma once
/// @file association.hpp
/// Object-level association: the paper's eq. 1 cost with Hungarian matching and gates, and
/// the FAPP baseline (greedy nearest centroid). Pure functions on small structs.

#include <vector>

#include <Eigen/Core>

#include "ucon/perception/params.hpp"

namespace ucon {
namespace perception {

/// An axis-aligned box in the x-y plane (projection of a 3-D box), centre and full size [m].
struct BoxXY {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d size = Eigen::Vector2d::Zero();  ///< side lengths, >= 0
};

/// Intersection over union of two x-y boxes, in [0, 1] (0 if either is empty).
double iouXY(const BoxXY& a, const BoxXY& b);

/// Generalised IoU of two x-y boxes, in (-1, 1]: IoU minus the share of their enclosing box
/// covered by neither.
double giouXY(const BoxXY& a, const BoxXY& b);

/// A current detection c.
struct DetectionView {
  BoxXY box;
};

/// A track h, predicted to the current frame.
struct TrackView {
  BoxXY box;                       ///< predicted centre, track's size
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< filtered velocity [m/s]
  bool has_velocity = false;       ///< false for a track with a single measurement
  Eigen::Vector2d last_center = Eigen::Vector2d::Zero();  ///< last measured centre [m]
  double since_last = 0.0;         ///< time since that measurement [s], >= 0
  Eigen::Matrix2d position_cov = Eigen::Matrix2d::Zero();  ///< predicted x-y covariance [m^2]
  Eigen::Vector2d seen_velocity = Eigen::Vector2d::Zero();  ///< filtered velocity when last measured [m/s]
};

/// Cross-heading gate of a track unseen for a while. People hidden behind something keep
/// their line (they speed up, stop or turn back along it) far more often than they step
/// sideways, while another person walking a neighbouring line is exactly a sideways step
/// away: a track unseen for at least cross_gate_after and at most cross_gate_until, last seen
/// moving faster than direction_min_speed, only takes a centre within cross_gate +
/// cross_gate_growth * unseen across the line through its predicted centre along the heading
/// it was last seen on. A real sideways return is rejected at first and comes back through
/// re-identification; after cross_gate_until (long enough to hide a turn) the gate is off.
/// True when the gate is off or does not apply.
bool passesCrossGate(const Eigen::Vector2d& center, const TrackView& h, const AssociationParams& p);

/// Squared Mahalanobis distance of a detection centre from a track's predicted centre, with
/// the track's predicted x-y covariance plus centroid_std^2 on the diagonal.
double mahalanobis2(const DetectionView& c, const TrackView& h, const AssociationParams& p);

/// Centre-distance gate of a track [m]: max_distance grown by distance_growth per second
/// unseen (a coasting prediction drifts), capped at max_distance_cap.
double distanceGate(const TrackView& h, const AssociationParams& p);

/// Eq. 1: f(c,h) = mu1 (1 - u(c,h)) + mu2 (1 - v^_c . v^_h) + mu3 |s_c - s_h| / |s_h|, with
/// `mu` = (mu1, mu2, mu3) and u the generalised IoU of the x-y boxes (= IoU when one box
/// contains the other; see .cpp).
///
/// The direction of c is the velocity the pair implies, (centre_c - last centre_h) / dt.
/// Directions of slow objects are noise and a new track has none: the direction term is
/// scaled by min(1, min(|v_c|, |v_h|) / direction_min_speed), and is 0 without a velocity.
/// |s_h| is floored at size_floor (a track box shrunk by partial views stays comparable).
double associationCost(const DetectionView& c, const TrackView& h, const std::vector<double>& mu,
                       const AssociationParams& p);

/// Re-identification ranking (lower is better) of a candidate last seen at `last` with velocity
/// `seen_velocity`, `dt` seconds before a new track appeared at `first`. People mostly keep
/// their line while hidden (they speed up, stop or turn back along it): the displacement is
/// measured along the last heading over reid_speed*dt + reid_margin and across it over
/// reid_cross_speed*dt + reid_margin, and the squared sum is scaled back to metres. Without a
/// heading (slower than confirm_min_speed) or with reid_cross_speed 0: the plain distance.
double reidentificationScore(const Eigen::Vector2d& first, const Eigen::Vector2d& last,
                             const Eigen::Vector2d& seen_velocity, double dt, const TrackParams& p);

/// Centre distance by which gated pairs are ranked [m]: for a track unseen for at least
/// cross_gate_after and last seen moving faster than direction_min_speed, the offset across
/// its last heading counts cross_rank_weight times (a hidden person more likely sped up,
/// stopped or turned back along the line than stepped sideways); otherwise the plain distance.
double rankingDistance(const Eigen::Vector2d& center, const TrackView& h, const AssociationParams& p);

/// Matching result: for each detection the matched track index, or -1; and the reverse.
struct Matching {
  std::vector<int> detection_to_track;
  std::vector<int> track_to_detection;
};

/// UCON: Hungarian matching on eq. 1 (weights `mu`); pairs above cost_gate, with centres farther than
/// distanceGate(), outside the Mahalanobis gate or failing passesCrossGate() are forbidden.
/// With cascade_after > 0 the tracks seen within cascade_after are matched first and the
/// others then match the detections left (a matching cascade by time unseen).
Matching associateObjects(const std::vector<DetectionView>& detections, const std::vector<TrackView>& tracks,
                          const std::vector<double>& mu, const AssociationParams& p);

/// FAPP baseline: repeatedly take the closest remaining (track, detection) centre pair
/// within fapp_gate [m] (ties broken by lower track, then detection index).
Matching associateNearest(const std::vector<DetectionView>& detections,
                          const std::vector<TrackView>& tracks, const AssociationParams& p);

}  // namespace perception
}  // namespace ucon
