#include "ucon/perception/association.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "ucon/mot/hungarian.hpp"

namespace ucon {
namespace perception {

double iouXY(const BoxXY& a, const BoxXY& b) {
  if (!(a.size.x() > 0 && a.size.y() > 0 && b.size.x() > 0 && b.size.y() > 0)) return 0.0;
  const Eigen::Vector2d amin = a.center - 0.5 * a.size, amax = a.center + 0.5 * a.size;
  const Eigen::Vector2d bmin = b.center - 0.5 * b.size, bmax = b.center + 0.5 * b.size;
  const double ix = std::min(amax.x(), bmax.x()) - std::max(amin.x(), bmin.x());
  const double iy = std::min(amax.y(), bmax.y()) - std::max(amin.y(), bmin.y());
  if (!(ix > 0 && iy > 0)) return 0.0;
  const double inter = ix * iy;
  return inter / (a.size.prod() + b.size.prod() - inter);
}

double giouXY(const BoxXY& a, const BoxXY& b) {
  const double iou = iouXY(a, b);
  const Eigen::Vector2d lo = (a.center - 0.5 * a.size).cwiseMin(b.center - 0.5 * b.size);
  const Eigen::Vector2d hi = (a.center + 0.5 * a.size).cwiseMax(b.center + 0.5 * b.size);
  const double hull = (hi - lo).prod();
  if (!(hull > 0.0)) return iou;
  const double inter = iou > 0.0 ? iou * (a.size.prod() + b.size.prod()) / (1.0 + iou) : 0.0;
  const double uni = a.size.prod() + b.size.prod() - inter;
  return iou - (hull - uni) / hull;
}

double associationCost(const DetectionView& c, const TrackView& h, const std::vector<double>& mu,
                       const AssociationParams& p) {
  // Term 1: x-y overlap of c's box and h's box at its predicted position. u is the
  // generalised IoU (equal to the IoU minus the share of the enclosing box not covered by
  // either box): for overlapping boxes it behaves like the paper's IoU, and once the boxes
  // stop overlapping (a coasting track, a small fast object) it keeps ranking candidates by
  // how far apart they are instead of scoring them all 1.
  const double iou = giouXY(c.box, h.box);
  // Term 2: motion direction agreement, faded out for slow or new objects (see header).
  double dir = 0.0;
  if (h.has_velocity && h.since_last > 1e-6) {
    const Eigen::Vector2d vc = (c.box.center - h.last_center) / h.since_last;
    const double sc = vc.norm(), sh = h.velocity.norm();
    if (sc > 1e-9 && sh > 1e-9) {
      const double w = std::min(1.0, std::min(sc, sh) / p.direction_min_speed);
      const double cosang = std::clamp(vc.dot(h.velocity) / (sc * sh), -1.0, 1.0);
      dir = w * (1.0 - cosang);
    }
  }
  // Term 3: relative size change; |s_h| floored at size_floor: a track box shrunk by partial
  // views (a few centimetres) would make any full view of the same object look like a
  // different object.
  const double sh = std::max(h.box.size.norm(), std::max(p.size_floor, 0.05));
  const double size = (c.box.size - h.box.size).norm() / sh;
  return mu[0] * (1.0 - iou) + mu[1] * dir + mu[2] * size;
}

double mahalanobis2(const DetectionView& c, const TrackView& h, const AssociationParams& p) {
  Eigen::Matrix2d S = h.position_cov;
  S.diagonal().array() += p.centroid_std * p.centroid_std;
  const Eigen::Vector2d r = c.box.center - h.box.center;
  const double det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
  if (!(det > 0.0) || !std::isfinite(det)) return INFINITY;
  // r' S^-1 r with the closed-form 2x2 inverse.
  return (S(1, 1) * r.x() * r.x() - (S(0, 1) + S(1, 0)) * r.x() * r.y() + S(0, 0) * r.y() * r.y()) / det;
}

namespace {

/// Offsets of r along the unit heading u and across it (positive to its left).
Eigen::Vector2d alongCross(const Eigen::Vector2d& r, const Eigen::Vector2d& u) {
  return {r.dot(u), u.x() * r.y() - u.y() * r.x()};
}

/// The unit heading a track was last seen moving on, when it has been unseen for at least
/// cross_gate_after and was faster than direction_min_speed; zero otherwise.
Eigen::Vector2d coastingHeading(const TrackView& h, const AssociationParams& p) {
  const double speed = h.seen_velocity.norm();
  if (!(h.since_last >= p.cross_gate_after) || !(speed >= p.direction_min_speed)) return Eigen::Vector2d::Zero();
  return h.seen_velocity / speed;
}

}  // namespace

double reidentificationScore(const Eigen::Vector2d& first, const Eigen::Vector2d& last,
                             const Eigen::Vector2d& seen_velocity, double dt, const TrackParams& p) {
  const Eigen::Vector2d r = first - last;
  const double s_along = p.reid_speed * dt + p.reid_margin;
  const double speed = seen_velocity.norm();
  if (p.reid_cross_speed <= 0.0 || !(speed >= p.confirm_min_speed) || !(s_along > 0.0)) return r.norm();
  const Eigen::Vector2d ac = alongCross(r, seen_velocity / speed);
  const double along = ac.x(), cross = ac.y();
  const double s_cross = p.reid_cross_speed * dt + p.reid_margin;
  return s_along * std::sqrt((along * along) / (s_along * s_along) + (cross * cross) / (s_cross * s_cross));
}

double distanceGate(const TrackView& h, const AssociationParams& p) {
  return std::min(p.max_distance_cap, p.max_distance + p.distance_growth * std::max(0.0, h.since_last));
}

bool passesCrossGate(const Eigen::Vector2d& center, const TrackView& h, const AssociationParams& p) {
  if (!(p.cross_gate > 0.0) || !(h.since_last <= p.cross_gate_until)) return true;
  const Eigen::Vector2d u = coastingHeading(h, p);
  if (u.isZero()) return true;
  return std::abs(alongCross(center - h.box.center, u).y()) <= p.cross_gate + p.cross_gate_growth * h.since_last;
}

double rankingDistance(const Eigen::Vector2d& center, const TrackView& h, const AssociationParams& p) {
  const Eigen::Vector2d r = center - h.box.center;
  const Eigen::Vector2d u = p.cross_rank_weight > 1.0 ? coastingHeading(h, p) : Eigen::Vector2d::Zero();
  if (u.isZero()) return r.norm();
  const Eigen::Vector2d ac = alongCross(r, u);
  const double along = ac.x(), cross = p.cross_rank_weight * ac.y();
  return std::sqrt(along * along + cross * cross);
}

Matching associateObjects(const std::vector<DetectionView>& detections, const std::vector<TrackView>& tracks,
                          const std::vector<double>& mu, const AssociationParams& p) {
  Matching m;
  m.detection_to_track.assign(detections.size(), -1);
  m.track_to_detection.assign(tracks.size(), -1);
  if (detections.empty() || tracks.empty()) return m;
  CostMatrix cost(static_cast<int>(detections.size()), static_cast<int>(tracks.size()));
  for (int i = 0; i < cost.rows; ++i) {
    for (int j = 0; j < cost.cols; ++j) {
      const double d = (detections[i].box.center - tracks[j].box.center).norm();
      if (!(d <= distanceGate(tracks[j], p))) continue;
      if (p.gate_sigma > 0.0 && !(mahalanobis2(detections[i], tracks[j], p) <= p.gate_sigma * p.gate_sigma)) continue;
      if (!passesCrossGate(detections[i].box.center, tracks[j], p)) continue;
      const double f = associationCost(detections[i], tracks[j], mu, p);
      // The gate applies to eq. 1; the distance term only ranks the pairs that pass it (a
      // long-coasting track with a wide gate must not win over a nearer one).
      if (std::isfinite(f) && f <= p.cost_gate) cost(i, j) = f + p.distance_weight * rankingDistance(detections[i].box.center, tracks[j], p);
    }
  }
  // Matching cascade: tracks seen within cascade_after first, then the others on the
  // detections left. A coasting track's wide gates and faded direction term must not let it
  // outbid the track that is still following a partly hidden object.
  const auto solve = [&](bool recent_only) {
    CostMatrix stage(cost.rows, cost.cols);  // the pairs still open in this stage
    bool any = false;
    for (int i = 0; i < cost.rows; ++i) {
      if (m.detection_to_track[i] >= 0) continue;
      for (int j = 0; j < cost.cols; ++j) {
        if (m.track_to_detection[j] >= 0 || (recent_only && tracks[j].since_last > p.cascade_after)) continue;
        stage(i, j) = cost(i, j);
        any = any || std::isfinite(stage(i, j));
      }
    }
    if (!any) return;
    const std::vector<int> a = solveAssignment(stage);
    for (int i = 0; i < cost.rows; ++i) {
      if (a[i] < 0) continue;
      m.detection_to_track[i] = a[i];
      m.track_to_detection[a[i]] = i;
    }
  };
  if (p.cascade_after > 0.0) solve(true);
  solve(false);
  return m;
}

Matching associateNearest(const std::vector<DetectionView>& detections,
                          const std::vector<TrackView>& tracks, const AssociationParams& p) {
  Matching m;
  m.detection_to_track.assign(detections.size(), -1);
  m.track_to_detection.assign(tracks.size(), -1);
  std::vector<std::tuple<double, int, int>> pairs;
  for (int j = 0; j < static_cast<int>(tracks.size()); ++j) {
    for (int i = 0; i < static_cast<int>(detections.size()); ++i) {
      const double d = (detections[i].box.center - tracks[j].box.center).norm();
      if (d <= p.fapp_gate) pairs.emplace_back(d, j, i);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [d, j, i] : pairs) {
    if (m.track_to_detection[j] >= 0 || m.detection_to_track[i] >= 0) continue;
    m.track_to_detection[j] = i;
    m.detection_to_track[i] = j;
  }
  return m;
}

}  // namespace perception
}  // namespace ucon
