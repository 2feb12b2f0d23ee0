#include "ucon/perception/track_manager.hpp"

#include <algorithm>
#include <cmath>

#include "ucon/perception/registration.hpp"
#include "ucon/tracked_object_t.hpp"

namespace ucon {
namespace perception {

namespace {

using TO = tracked_object_t;

double seconds(int64_t dt_us) { return static_cast<double>(dt_us) * 1e-6; }

/// Points kept per measurement for the registration velocity: the alignment costs
/// O(iterations * n^2) per track and frame.
constexpr int kRegistrationPoints = 40;

Points thin(const Points& pts, int max_points) {
  if (static_cast<int>(pts.size()) <= max_points) return pts;
  Points out;
  out.reserve(static_cast<std::size_t>(max_points));
  for (int k = 0; k < max_points; ++k)
    out.push_back(pts[static_cast<std::size_t>(k) * pts.size() / static_cast<std::size_t>(max_points)]);
  return out;
}

}  // namespace

TrackManager::TrackManager(const PerceptionParams& params, const AngularGrid& coarse)
    : params_(params.tracks),
      kalman_(params.kalman),
      max_history_points_(params.reassociation.max_history_points),
      coarse_(coarse) {}

void TrackManager::predict(int64_t utime, StatusReport& status) {
  // All filters live at the time of the last processed frame; advance them to this one.
  const double dt = last_utime_ > 0 ? seconds(utime - last_utime_) : 0.0;
  last_utime_ = utime;
  last_dt_ = dt;
  if (dt <= 0.0) return;
  for (auto& tr : tracks_) {
    if (tr.kf.predict(dt) != kalman::KalmanStatus::kOk) status.count("kalman_errors");
  }
}

std::vector<Eigen::Vector2d> TrackManager::predictedCenters() const {
  std::vector<Eigen::Vector2d> c;
  c.reserve(tracks_.size());
  for (const auto& tr : tracks_) c.push_back(tr.kf.state().head<2>());
  return c;
}

std::vector<TrackView> TrackManager::views(int64_t utime) const {
  std::vector<TrackView> v;
  v.reserve(tracks_.size());
  for (const auto& tr : tracks_) {
    TrackView t;
    t.box.center = tr.kf.state().head<2>();
    t.box.size = tr.size;
    t.velocity = tr.kf.state().segment<2>(3);
    t.has_velocity = tr.measured.size() >= 2;
    t.last_center = tr.measured.empty() ? t.box.center : tr.measured.back().center.head<2>();
    t.since_last = seconds(utime - tr.last_seen_utime);
    t.position_cov = tr.kf.covariance().topLeftCorner<2, 2>();
    t.seen_velocity = tr.seen_velocity;
    v.push_back(t);
  }
  return v;
}

void TrackManager::update(std::size_t j, const Measurement& m, int64_t utime, int8_t how, bool moving,
                          bool on_structure, StatusReport& status) {
  Track& t = tracks_[j];
  const TrackParams& p = params_;
  t.structure_frames = on_structure ? t.structure_frames + 1 : 0;
  if ((m.center.head<2>() - t.arrival_xy).norm() > p.structure_arrival_distance) {
    t.arrival_xy = m.center.head<2>();
    t.arrival_utime = utime;
  }
  const int64_t baseline_us = static_cast<int64_t>(p.velocity_baseline * 1e6);
  // Differenced velocity against the newest measurement at least one baseline old (or the
  // oldest one kept): a longer baseline than one frame keeps the centroid noise down.
  const Track::Measured* ref = nullptr;
  for (const auto& e : t.measured) {
    if (utime - e.utime >= baseline_us || ref == nullptr) ref = &e;
  }
  Points points = p.registration_velocity ? thin(m.points, kRegistrationPoints) : Points{};
  kalman::KalmanStatus st;
  if (ref && utime > ref->utime) {
    const double dt = seconds(utime - ref->utime);
    Eigen::Vector3d v = (m.center - ref->center) / dt;
    if (p.registration_velocity && !m.occluded && !m.cut) {
      // The shared surface's displacement, from where the filter expects it (or, with no
      // velocity yet, from the centres' difference).
      const Eigen::Vector2d guess = t.measured.size() >= 2 ? Eigen::Vector2d(t.kf.state().segment<2>(3) * dt)
                                                            : Eigen::Vector2d(v.head<2>() * dt);
      Eigen::Vector2d d;
      if (registerTranslation(ref->points, points, guess, RegistrationParams{}, &d)) {
        v.head<2>() = d / dt;
        status.count("velocity_registered");
      }
    }
    st = t.kf.update(m.center, v);
  } else {
    st = t.kf.updatePosition(m.center);
  }
  if (st != kalman::KalmanStatus::kOk) {
    status.count("kalman_errors");
    t.kf.init(m.center, Eigen::Vector3d::Zero());
  }
  t.measured.push_back({utime, m.center, std::move(points)});
  while (t.measured.size() > 2 && utime - t.measured[1].utime >= baseline_us) t.measured.pop_front();
  if (m.cut) status.count("views_anchored");
  if (!m.occluded) {  // the width and box of a view cut by an occluder are not the object's
    t.size = (1.0 - p.size_smoothing) * t.size + p.size_smoothing * m.box.size;
    // Views missing a side without a visible occluder (sparse returns) are common, views wider
    // than the object are not: the width follows increases faster than decreases.
    const double w = m.width >= t.width ? p.size_smoothing : 0.25 * p.size_smoothing;
    t.width = t.width > 0.0 ? (1.0 - w) * t.width + w * m.width : m.width;
  }
  t.size_z = (1.0 - p.size_smoothing) * t.size_z + p.size_smoothing * m.size_z;
  t.history = thin(m.points, max_history_points_);
  t.last_seen_utime = utime;
  t.seen_velocity = t.kf.state().segment<2>(3);
  ++t.hits;
  t.misses = 0;
  t.num_points = static_cast<int>(m.points.size());
  t.last_association = how;
  t.consecutive_reassoc = how == TO::ASSOC_REASSOCIATED ? t.consecutive_reassoc + 1 : 0;
  if (moving) {
    ++t.moving_hits;
    t.last_moving_utime = utime;
  }
}

void TrackManager::reidCandidate(const Track& fresh, Track** coasting, const Lost** lost) {
  // The object a coasting track lost may come back as a new track (it turned while hidden,
  // or reappeared farther than the association gates): a new track that is where that object
  // could have walked to since it was last seen is that object.
  *coasting = nullptr;
  *lost = nullptr;
  const TrackParams& p = params_;
  if (p.reid_speed <= 0.0 || fresh.measured.empty()) return;
  const Eigen::Vector2d first = fresh.first_center;
  const auto score = [&](const Eigen::Vector2d& last, const Eigen::Vector2d& v, double dt) {
    return reidentificationScore(first, last, v, dt, p);
  };
  double best_d = 0.0;
  for (auto& tr : tracks_) {
    if (&tr == &fresh || tr.state != TO::STATE_COASTING || tr.measured.empty()) continue;
    if (tr.last_seen_utime > fresh.created_utime) continue;  // both seen at once: two objects
    const double dt = seconds(fresh.created_utime - tr.last_seen_utime);
    const Eigen::Vector2d last = tr.measured.back().center.head<2>();
    if ((first - last).norm() > p.reid_speed * dt + p.reid_margin) continue;
    const double d = score(last, tr.seen_velocity, dt);
    if (!*coasting || d < best_d) *coasting = &tr, best_d = d;
  }
  // Recently deleted confirmed tracks are candidates too (a coasting track may have been
  // seen through or timed out before its object came back).
  for (const auto& l : lost_) {
    if (l.last_seen_utime > fresh.created_utime) continue;
    const double dt = seconds(fresh.created_utime - l.last_seen_utime);
    if ((first - l.last_center).norm() > p.reid_speed * dt + p.reid_margin) continue;
    const double d = score(l.last_center, l.seen_velocity, dt);
    if ((!*coasting && !*lost) || d < best_d) *lost = &l, *coasting = nullptr, best_d = d;
  }
}

TrackManager::Lost TrackManager::lostRecord(const Track& t) {
  return {t.id, t.age_frames, t.measured.back().center.head<2>(), t.seen_velocity, t.last_seen_utime};
}

Eigen::Vector3d TrackManager::returningVelocity(const Track& fresh) {
  // The object a coasting or recently deleted track lost, back where it would be had it kept
  // its velocity: the new track starts with that velocity (its initial uncertainty stays).
  Track* coasting = nullptr;
  const Lost* lost = nullptr;
  reidCandidate(fresh, &coasting, &lost);
  if (!coasting && !lost) return Eigen::Vector3d::Zero();
  const Lost was = coasting ? lostRecord(*coasting) : *lost;
  const Eigen::Vector2d& v = was.seen_velocity;
  if (!v.allFinite()) return Eigen::Vector3d::Zero();
  const double dt = seconds(fresh.created_utime - was.last_seen_utime);
  const Eigen::Vector2d predicted = was.last_center + v * dt;
  if ((fresh.first_center - predicted).norm() > params_.reid_margin + 0.25 * v.norm() * dt) return Eigen::Vector3d::Zero();
  return Eigen::Vector3d(v.x(), v.y(), 0.0);
}

void TrackManager::reidentify(Track& fresh, Track* best, const Lost* best_lost, StatusReport& status) {
  // The newly confirmed track takes over the identity of the object it is (reidCandidate()),
  // and a coasting track of that object ends.
  if (best) {
    fresh.id = best->id;
    fresh.age_frames = best->age_frames;
    best->state = TO::STATE_DELETED;
    best->reidentified = true;
  } else if (best_lost) {
    fresh.id = best_lost->id;
    fresh.age_frames = best_lost->age_frames;
    const int64_t id = best_lost->id;
    lost_.erase(std::remove_if(lost_.begin(), lost_.end(), [id](const Lost& l) { return l.id == id; }), lost_.end());
  } else {
    return;
  }
  status.count("reidentifications");
}

bool TrackManager::seenThrough(const Track& t, const Frame& frame) const {
  // The nearest return over the track's bin and its 8 neighbours: conservative, the
  // prediction may be a bin off and a few returns of the object itself keep it alive.
  const Eigen::Vector3f ray = t.kf.state().head<3>().cast<float>() - frame.sensor_origin;
  const int n_az = coarse_.azimuthBins(), n_el = coarse_.elevationBins();
  float nearest = INFINITY;
  if (!frame.nearest_coarse.empty()) {
    const int b = coarse_.bin(ray), a0 = b / n_el, e0 = b % n_el;
    for (int da = -1; da <= 1; ++da)
      for (int de = -1; de <= 1; ++de) {
        const int a = (a0 + da + n_az) % n_az, e = e0 + de;
        if (e < 0 || e >= n_el) continue;
        nearest = std::min(nearest, frame.nearest_coarse[static_cast<std::size_t>(a * n_el + e)]);
      }
  }
  return std::isfinite(nearest) && nearest > ray.norm() + static_cast<float>(params_.free_margin);
}

void TrackManager::manage(int64_t utime, const std::vector<char>& updated, const Frame& frame, StatusReport& status) {
  const TrackParams& p = params_;
  for (std::size_t j = 0; j < updated.size(); ++j) {
    Track& tr = tracks_[j];
    ++tr.age_frames;
    if (updated[j]) {
      const double speed = tr.kf.state().segment<2>(3).norm();
      const double moved = tr.measured.empty() ? 0.0 : (tr.measured.back().center.head<2>() - tr.first_center).norm();
      bool confirm = false;
      Track* coasting = nullptr;  // the object this track is, if it was tracked before
      const Lost* lost = nullptr;
      if (tr.state == TO::STATE_TENTATIVE && tr.hits >= p.confirm_hits && speed <= p.confirm_max_speed &&
          tr.moving_hits >= p.confirm_moving_hits) {
        confirm = speed >= p.confirm_min_speed && moved >= p.confirm_min_distance;
        if (confirm || p.reid_confirm) reidCandidate(tr, &coasting, &lost);  // needed for either
        // An object already known to move, back where it could be (from hiding, or standing
        // since it was lost): the speed and distance tests would keep a person who stands
        // or walks slowly tentative until the track expires, again and again.
        if (!confirm && p.reid_confirm && (coasting || lost)) {
          confirm = true;
          status.count("tracks_confirmed_returning");
        }
      }
      if (confirm) {
        tr.state = TO::STATE_CONFIRMED;
        tr.confirmed_once = true;
        status.count("tracks_confirmed");
        reidentify(tr, coasting, lost, status);
      } else if (tr.state == TO::STATE_COASTING) {
        tr.state = TO::STATE_CONFIRMED;
      }
    } else {
      ++tr.misses;
      tr.num_points = 0;
      // Negative evidence: the sensor sees through where the track should be (the nearest
      // return in that direction lies well behind it), so the object is not there.
      tr.free_count = seenThrough(tr, frame) ? tr.free_count + 1 : 0;
      if (tr.free_count >= p.free_frames) tr.state = TO::STATE_DELETED;
      // Unseen objects (people) stop and turn more often than they keep straight on: let the
      // coasting velocity decay instead of extrapolating it at full speed. The covariance
      // keeps growing through the filter's own prediction.
      if (p.coast_velocity_decay > 0.0 && last_dt_ > 0.0) {
        kalman::State6 x = tr.kf.state();
        x.tail<3>() *= std::exp(-last_dt_ / p.coast_velocity_decay);
        if (tr.kf.initState(x, tr.kf.covariance()) != kalman::KalmanStatus::kOk) status.count("kalman_errors");
      }
      tr.last_association = TO::ASSOC_NONE;
      if (tr.state == TO::STATE_TENTATIVE) {
        if (tr.misses >= p.tentative_max_misses) tr.state = TO::STATE_DELETED;
      } else if (tr.state == TO::STATE_CONFIRMED) {
        tr.state = TO::STATE_COASTING;
      }
      if (seconds(utime - tr.last_seen_utime) > p.max_coast) tr.state = TO::STATE_DELETED;
    }
    if (tr.state == TO::STATE_TENTATIVE && seconds(utime - tr.created_utime) > p.tentative_max_age)
      tr.state = TO::STATE_DELETED;
    // Static clutter that a track latched onto (a pillar a person brushed): its clusters stop
    // passing the motion test, or its filtered speed stays near zero. People pause for
    // shorter than max_stationary (and a longer pause is bridged by re-identification).
    if (tr.kf.state().segment<2>(3).norm() >= p.confirm_min_speed) tr.last_fast_utime = utime;
    // A track that measures only what stood at its place before it came there has latched
    // onto structure (a box a person walked past, merged into one cluster with the person
    // when the track started; a pillar beside which it lost its person): it ends at once,
    // not after max_stationary.
    if (p.structure_frames > 0 && tr.structure_frames >= p.structure_frames) {
      tr.state = TO::STATE_DELETED;
      status.count("tracks_on_structure");
    }
    if (seconds(utime - tr.last_moving_utime) > p.max_stationary ||
        seconds(utime - std::max(tr.last_fast_utime, tr.created_utime)) > p.max_stationary)
      tr.state = TO::STATE_DELETED;
  }
  // Deleted confirmed tracks are remembered for re-identification for a while.
  for (const auto& tr : tracks_) {
    if (tr.state != TO::STATE_DELETED || tr.reidentified || tr.confirmed_once == false || tr.measured.empty()) continue;
    lost_.push_back(lostRecord(tr));
  }
  while (!lost_.empty() && seconds(utime - lost_.front().last_seen_utime) > p.reid_window) lost_.pop_front();
  const auto before = tracks_.size();
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(), [](const Track& tr) { return tr.state == TO::STATE_DELETED; }),
                tracks_.end());
  status.count("tracks_deleted", static_cast<int64_t>(before - tracks_.size()));
}

bool velocitySettled(const Track& t, double velocity_std) {
  return t.kf.covariance().block<2, 2>(3, 3).trace() <= 2.0 * velocity_std * velocity_std;
}

bool TrackManager::nearTrack(const Eigen::Vector2d& center) const {
  for (const auto& tr : tracks_)
    if ((tr.kf.state().head<2>() - center).norm() < params_.new_track_separation) return true;
  return false;
}

bool TrackManager::start(const Measurement& m, int64_t utime, StatusReport& status) {
  Track tr(kalman_);
  tr.id = next_id_++;
  tr.state = TO::STATE_TENTATIVE;
  tr.created_utime = utime;
  tr.size = m.box.size;
  tr.width = m.width;
  tr.size_z = m.size_z;
  tr.first_center = m.box.center;
  tr.history = thin(m.points, max_history_points_);
  tr.measured.push_back({utime, m.center, params_.registration_velocity ? thin(m.points, kRegistrationPoints) : Points{}});
  tr.last_seen_utime = utime;
  tr.hits = 1;
  tr.moving_hits = 1;
  tr.last_moving_utime = utime;
  tr.arrival_xy = m.center.head<2>();
  tr.arrival_utime = utime;
  tr.num_points = static_cast<int>(m.points.size());
  tr.last_association = TO::ASSOC_NEW;
  const Eigen::Vector3d v0 = params_.reid_velocity ? returningVelocity(tr) : Eigen::Vector3d::Zero();
  if (tr.kf.init(m.center, v0) != kalman::KalmanStatus::kOk) {
    status.count("kalman_errors");
    return false;
  }
  if (!v0.isZero()) status.count("tracks_started_returning");
  tracks_.push_back(std::move(tr));
  status.count("tracks_created");
  return true;
}

}  // namespace perception
}  // namespace ucon
