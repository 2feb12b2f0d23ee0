#include "ucon/perception/perception_node.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "ucon/fast_atan2.hpp"
#include "ucon/perception/footprint.hpp"
#include "ucon/perception/registration.hpp"
#include "ucon/perception/reassociation.hpp"
#include "ucon/tracked_object_t.hpp"

namespace ucon {
namespace perception {

namespace {

using TO = tracked_object_t;

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double seconds(int64_t dt_us) { return static_cast<double>(dt_us) * 1e-6; }

// Azimuth in [0, 2 pi] and elevation in [0, pi] of a direction (shifted to start at 0).
struct Angles {
  double az, el;
};

// For binning only: fastAtan2 is within 2e-5 rad of std::atan2, the bins are a degree or more.
Angles anglesOf(const Eigen::Vector3f& d) {
  return {fastAtan2(static_cast<double>(d.y()), static_cast<double>(d.x())) + M_PI,
          fastAtan2(static_cast<double>(d.z()), static_cast<double>(d.head<2>().norm())) + M_PI / 2};
}

int binOf(const Angles& a, double bin_deg, int n_az, int n_el) {
  const double bin = bin_deg * M_PI / 180.0;
  const int i = std::clamp(static_cast<int>(a.az / bin), 0, n_az - 1);
  const int j = std::clamp(static_cast<int>(a.el / bin), 0, n_el - 1);
  return i * n_el + j;
}

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

PerceptionNode::PerceptionNode(const PerceptionParams& params, Stopwatch stopwatch)
    : params_(params),
      stopwatch_(stopwatch ? std::move(stopwatch) : Stopwatch(steadySeconds)),
      poses_(2.0),
      persistence_(params.segmentation.static_cell, params.segmentation.static_persistence,
                   params.segmentation.static_max_gap),
      status_("perception") {
  const double bin = params_.segmentation.free_space_bin_deg;
  az_bins_ = static_cast<int>(std::ceil(360.0 / bin));
  el_bins_ = static_cast<int>(std::ceil(180.0 / bin));
  free_az_ = static_cast<int>(std::ceil(360.0 / params_.tracks.free_bin_deg));
  free_el_ = static_cast<int>(std::ceil(180.0 / params_.tracks.free_bin_deg));
  // Counters exist from the start so the status always lists them.
  for (const char* c : {"frames_in", "frames_processed", "frames_repeated", "frames_out_of_order",
                        "frames_bad_utime", "frames_malformed", "frames_bad_frame_id", "frames_empty",
                        "frames_no_pose", "frames_stale_pose", "points_in", "points_non_finite",
                        "poses_in", "poses_invalid", "poses_non_finite", "poses_out_of_order",
                        "tracks_created", "tracks_confirmed", "tracks_deleted", "reassociations",
                        "kalman_errors", "invalid_outputs", "reidentifications", "moving_parts_split",
                        "views_anchored", "velocity_registered"})
    status_.count(c, 0);
}

void PerceptionNode::onPose(const robot_pose_t& pose) {
  status_.count("poses_in");
  switch (poses_.add(pose)) {
    case PoseBuffer::AddResult::kAdded:
      clock_.observe(pose.utime);
      break;
    case PoseBuffer::AddResult::kInvalid:
      status_.count("poses_invalid");
      break;
    case PoseBuffer::AddResult::kNonFinite:
      status_.count("poses_non_finite");
      break;
    case PoseBuffer::AddResult::kOutOfOrder:
      status_.count("poses_out_of_order");
      break;
  }
}

PerceptionOutput PerceptionNode::invalidOutput(int64_t utime, int64_t frame_seq, const std::string& why) {
  PerceptionOutput out;
  tracked_objects_t o{};
  o.utime = utime;
  o.seq = objects_seq_++;
  o.valid = false;
  o.frame_seq = frame_seq;
  o.frame_id = "world";
  o.num_objects = 0;
  out.objects = std::move(o);
  static_points_t s{};
  s.utime = utime;
  s.seq = static_seq_++;
  s.valid = false;
  s.max_range = static_cast<float>(params_.preprocess.max_range);
  s.num_points = 0;
  out.static_points = std::move(s);
  last_output_utime_ = utime;
  status_.count("invalid_outputs");
  status_.setHealth(process_status_t::HEALTH_WARN, why);
  return out;
}

PerceptionOutput PerceptionNode::tick(int64_t utime) {
  if (utime <= 0) return {};
  const int64_t last = std::max(last_frame_utime_, last_output_utime_);
  if (utime - last <= static_cast<int64_t>(params_.frame_timeout * 1e6)) return {};
  return invalidOutput(utime, -1, "no LiDAR frame for more than frame_timeout");
}

PerceptionOutput PerceptionNode::onPoints(const point_cloud_t& cloud) {
  const double t_start = stopwatch_();
  status_.count("frames_in");
  if (cloud.utime <= 0) {
    status_.count("frames_bad_utime");
    return {};
  }
  if (cloud.utime == last_frame_utime_) {
    status_.count("frames_repeated");
    return {};
  }
  if (cloud.utime < last_frame_utime_) {
    status_.count("frames_out_of_order");
    return {};
  }
  const auto n = static_cast<std::size_t>(std::max(cloud.num_points, 0));
  if (cloud.num_points < 0 || cloud.x.size() != n || cloud.y.size() != n || cloud.z.size() != n) {
    status_.count("frames_malformed");
    return {};
  }
  last_frame_utime_ = cloud.utime;
  clock_.observe(cloud.utime);
  const int64_t utime = cloud.utime;
  if (cloud.frame_id != "base" && cloud.frame_id != "world") {
    status_.count("frames_bad_frame_id");
    return invalidOutput(utime, cloud.seq, "LIDAR_POINTS frame_id is '" + cloud.frame_id +
                                               "', expected 'base' or 'world'");
  }
  if (cloud.num_points == 0) {
    status_.count("frames_empty");
    return invalidOutput(utime, cloud.seq, "empty LiDAR frame");
  }
  const auto pose = poses_.at(utime, params_.pose_max_gap);
  if (!pose) {
    status_.count(poses_.empty() ? "frames_no_pose" : "frames_stale_pose");
    return invalidOutput(utime, cloud.seq, poses_.empty() ? "no ROBOT_POSE yet" : "ROBOT_POSE stale");
  }
  status_.count("frames_processed");
  status_.count("points_in", cloud.num_points);
  const Eigen::Isometry3d T = cloud.frame_id == "world" ? Eigen::Isometry3d::Identity() : *pose;
  last_robot_xy_ = pose->translation().head<2>();
  {
    // Where the points were measured from: the cloud's first sensor as the driver gives it, or
    // (clouds without origins, e.g. older logs) the configured origin in the base frame.
    const auto& so = params_.preprocess.sensor_origin;
    sensor_origin_d_ = cloud.num_sensors > 0
                           ? T * Eigen::Vector3d(cloud.origin_x[0], cloud.origin_y[0], cloud.origin_z[0])
                           : *pose * Eigen::Vector3d(so[0], so[1], so[2]);
    sensor_origin_ = sensor_origin_d_.cast<float>();
  }

  // 1. Pre-processing.
  double t = stopwatch_();
  preprocess(cloud, T);
  status_.time("preprocess", elapsedMs(t));

  // 2. Clustering, motion test, confirmation from tracks.
  t = stopwatch_();
  predictTracks(utime);
  segment();
  status_.time("segment", elapsedMs(t));

  // 3. Object-level association.
  t = stopwatch_();
  std::vector<int> dyn;  // detection indices that are dynamic
  for (int i = 0; i < static_cast<int>(last_detections_.size()); ++i)
    if (last_detections_[i].dynamic()) dyn.push_back(i);
  std::vector<DetectionView> dviews;
  for (int i : dyn) dviews.push_back({last_detections_[i].box});
  const std::vector<TrackView> tviews = trackViews(utime);
  const Matching match = params_.useUcon() ? associateObjects(dviews, tviews, params_.object_association)
                                           : associateNearest(dviews, tviews, params_.object_association);
  const std::size_t n_old_tracks = tracks_.size();
  std::vector<char> updated(n_old_tracks, 0);
  std::vector<char> dynamic_point(frame_points_.size(), 0);
  std::vector<char> det_done(last_detections_.size(), 0);
  std::vector<std::vector<int>> meas_points(n_old_tracks);  // measurement points per track
  std::vector<int8_t> meas_how(n_old_tracks, TO::ASSOC_NONE);
  std::vector<char> meas_moving(n_old_tracks, 0);
  for (std::size_t k = 0; k < dyn.size(); ++k) {
    const int j = match.detection_to_track[k];
    if (j < 0) continue;
    meas_points[j] = restrictToTrack(tracks_[j], last_detections_[dyn[k]].indices);
    meas_how[j] = TO::ASSOC_OBJECT;
    meas_moving[j] = movedShare(meas_points[j]) >= params_.segmentation.motion_ratio;
    det_done[dyn[k]] = 1;
  }
  status_.time("associate", elapsedMs(t));

  // 4. Point-level historical re-association of the tracks left unmatched (appendix
  // algorithm). P is every pre-processed point of the frame: the environment, the unmatched
  // clusters and also matched clusters, so that an object merged into another object's
  // cluster (or into static structure) is recovered and the merged cluster is split.
  t = stopwatch_();
  if (params_.useUcon() && params_.reassociation.enabled) {
    std::vector<int> lost;
    for (std::size_t j = 0; j < n_old_tracks; ++j) {
      const Track& tr = tracks_[j];
      // Tentative tracks are not recovered: a duplicate would steal its original's points.
      if (meas_how[j] == TO::ASSOC_NONE && tr.state != TO::STATE_TENTATIVE && !tr.history.empty() &&
          tr.consecutive_reassoc < params_.reassociation.max_consecutive)
        lost.push_back(static_cast<int>(j));
    }
    if (!lost.empty() && !frame_points_.empty()) {
      frame_index_.build(frame_points_, params_.reassociation.d0);  // only frames with a lost track need it
      std::vector<HistoricalObject> objs;
      for (int j : lost) {
        const Track& tr = tracks_[j];
        objs.push_back({tr.history, tr.kf.state().tail<3>(), seconds(utime - tr.last_seen_utime)});
      }
      const auto rec = reassociate(objs, frame_index_, params_.reassociation.d0, params_.reassociation.gamma);
      // Points already measured by an object-level match: the matched track keeps them unless
      // enough of its cluster remains without them.
      std::vector<int> owner(frame_points_.size(), -1);
      for (std::size_t j = 0; j < n_old_tracks; ++j)
        for (int i : meas_points[j]) owner[i] = static_cast<int>(j);
      std::vector<int> claimed_by(frame_points_.size(), -1);
      for (std::size_t k = 0; k < lost.size(); ++k)
        for (int i : rec[k]) claimed_by[i] = lost[k];
      for (std::size_t j = 0; j < n_old_tracks; ++j) {
        if (meas_how[j] != TO::ASSOC_OBJECT) continue;
        std::vector<int> rest;
        for (int i : meas_points[j])
          if (claimed_by[i] < 0) rest.push_back(i);
        if (rest.size() == meas_points[j].size()) continue;
        const std::size_t keep_min = std::max<std::size_t>(
            static_cast<std::size_t>(params_.segmentation.min_cluster_points), (3 * meas_points[j].size()) / 10);
        if (params_.reassociation.split_matched && rest.size() >= keep_min) {
          meas_points[j] = std::move(rest);  // split the merged cluster
        } else {
          for (int i : meas_points[j]) claimed_by[i] = -1;  // the match keeps its points
        }
      }
      for (std::size_t k = 0; k < lost.size(); ++k) {
        const int j = lost[k];
        std::vector<int> mine;
        for (int i : rec[k])
          if (claimed_by[i] == j) mine.push_back(i);
        if (mine.size() < 2) continue;  // what is left after the split is too little to measure
        // Points centred away from the prediction belong to something else (typically the
        // occluder in front of a hidden object): not a recovery.
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        for (int i : mine) c += frame_points_[i].head<2>().cast<double>();
        c /= static_cast<double>(mine.size());
        if ((c - tracks_[j].kf.state().head<2>()).norm() > params_.reassociation.max_shift) continue;
        // Nor a neighbour on the next line (see passesCrossGate), judged by the view-corrected
        // centre, as object-level association judges a cluster.
        const Eigen::Vector2d view_c = viewCorrectedCenter(frame_points_, mine, sensor_origin_.head<2>().cast<double>(),
                                                           params_.segmentation.view_center_shift);
        if (!passesCrossGate(view_c, tviews[j], params_.object_association)) continue;
        meas_points[j] = std::move(mine);
        meas_how[j] = TO::ASSOC_REASSOCIATED;
        status_.count("reassociations");
      }
      // An unmatched cluster mostly taken by recovered objects is theirs: no new track.
      for (int i : dyn) {
        if (det_done[i]) continue;
        const auto& ind = last_detections_[i].indices;
        const auto taken = std::count_if(ind.begin(), ind.end(), [&](int p) { return claimed_by[p] >= 0; });
        if (2 * taken >= static_cast<long>(ind.size())) {
          det_done[i] = 1;
          for (int p : ind) dynamic_point[p] = 1;
        }
      }
    }
  }
  for (std::size_t j = 0; j < n_old_tracks; ++j) {
    if (meas_how[j] == TO::ASSOC_NONE || meas_points[j].empty()) continue;
    applyMeasurement(tracks_[j], measure(meas_points[j], &tracks_[j]), utime, meas_how[j], meas_moving[j] != 0);
    updated[j] = 1;
    for (int i : meas_points[j]) dynamic_point[i] = 1;
  }
  status_.time("reassociate", elapsedMs(t));

  // 5. Track management: new tracks from unmatched moving clusters, state machine.
  t = stopwatch_();
  manageTracks(utime, updated);
  for (int i : dyn) {
    const Detection& d = last_detections_[i];
    if (det_done[i] || !d.moving) continue;
    // A fragment of an object already tracked (or its re-detection right beside it) does not
    // start a second track.
    bool near_track = false;
    for (std::size_t j = 0; j < tracks_.size() && !near_track; ++j)
      near_track = (tracks_[j].kf.state().head<2>() - d.box.center).norm() < params_.tracks.new_track_separation;
    if (near_track) continue;
    Track tr(params_.kalman);
    tr.id = next_track_id_++;
    tr.state = TO::STATE_TENTATIVE;
    tr.created_utime = utime;
    const Measurement m = measure(d.indices);
    if (tr.kf.init(m.center, Eigen::Vector3d::Zero()) != kalman::KalmanStatus::kOk) {
      status_.count("kalman_errors");
      continue;
    }
    tr.size = m.box.size;
    tr.width = m.width;
    tr.size_z = m.size_z;
    tr.first_center = m.box.center;
    tr.history = thin(m.points, params_.reassociation.max_history_points);
    tr.measured.push_back(
        {utime, m.center, params_.tracks.registration_velocity ? thin(m.points, kRegistrationPoints) : Points{}});
    tr.last_seen_utime = utime;
    tr.hits = 1;
    tr.moving_hits = 1;
    tr.last_moving_utime = utime;
    tr.num_points = static_cast<int>(m.points.size());
    tr.last_association = TO::ASSOC_NEW;
    tracks_.push_back(std::move(tr));
    status_.count("tracks_created");
    for (int p : d.indices) dynamic_point[p] = 1;
  }
  status_.time("track", elapsedMs(t));

  PerceptionOutput out;
  out.objects = buildObjects(utime, cloud.seq);
  const std::vector<char> tracked_point = dynamic_point;  // before persistence marks new structure
  t = stopwatch_();
  if (params_.segmentation.static_persistence > 0.0) {
    persistence_.update(utime, frame_points_, &persistent_);
    for (std::size_t i = 0; i < frame_points_.size(); ++i)
      if (!persistent_[i]) dynamic_point[i] = 1;
  }
  status_.time("persistence", elapsedMs(t));
  out.static_points = buildStatic(utime, *pose, dynamic_point);
  t = stopwatch_();
  pushHistory(utime, tracked_point);
  status_.time("history", elapsedMs(t));
  last_output_utime_ = utime;

  int confirmed = 0;
  for (const auto& tr : tracks_) confirmed += tr.state == TO::STATE_CONFIRMED || tr.state == TO::STATE_COASTING;
  status_.set("tracks", static_cast<double>(tracks_.size()));
  status_.set("tracks_confirmed", confirmed);
  status_.set("points_per_frame", static_cast<double>(frame_points_.size()));
  status_.set("detections", static_cast<double>(last_detections_.size()));
  status_.set("dynamic_detections", static_cast<double>(dyn.size()));
  status_.setHealth(process_status_t::HEALTH_OK, "");
  last_frame_ms_ = elapsedMs(t_start);
  status_.time("total", last_frame_ms_);
  return out;
}

void PerceptionNode::preprocess(const point_cloud_t& cloud, const Eigen::Isometry3d& T) {
  const PreprocessParams& p = params_.preprocess;
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f tr = T.translation().cast<float>();
  const Eigen::Vector3f centre = tr;  // robot centre in the world
  const float min_r2 = static_cast<float>(p.min_range * p.min_range);
  const float max_r2 = static_cast<float>(p.max_range * p.max_range);
  Points kept;
  kept.reserve(static_cast<std::size_t>(cloud.num_points));
  frame_returns_.clear();
  int64_t non_finite = 0;
  const bool in_world = cloud.frame_id == "world";  // once, not a string compare per point
  // Several sensors: only the first one's returns are free-space evidence, since the free-space
  // test casts rays from that sensor's origin (another sensor's ray starts elsewhere).
  const bool several = cloud.num_sensors > 1 && cloud.num_point_sensors == cloud.num_points;
  for (int i = 0; i < cloud.num_points; ++i) {
    const Eigen::Vector3f b(cloud.x[i], cloud.y[i], cloud.z[i]);
    if (!b.allFinite()) {
      ++non_finite;
      continue;
    }
    const Eigen::Vector3f w = in_world ? b : Eigen::Vector3f(R * b + tr);
    const float r2 = (w.head<2>() - centre.head<2>()).squaredNorm();
    if (r2 < min_r2) continue;
    // Ground and far returns are not objects, but the space their rays crossed was free: the
    // motion test needs that (a mover's lower half is seen against the ground).
    if (!several || cloud.point_sensor[static_cast<std::size_t>(i)] == 0) frame_returns_.push_back(w);
    if (r2 > max_r2) continue;
    if (w.z() < p.min_height || w.z() > p.max_height) continue;
    kept.push_back(w);
  }
  if (non_finite) status_.count("points_non_finite", non_finite);
  // Merge the previous frame(s): at 50 Hz a person 10 m away gets only a handful of returns
  // per frame. Motion blur over 20 ms is a few centimetres.
  recent_cropped_.push_back(std::move(kept));
  while (static_cast<int>(recent_cropped_.size()) > p.accumulate_frames) recent_cropped_.pop_front();
  Points merged;
  for (const auto& f : recent_cropped_) merged.insert(merged.end(), f.begin(), f.end());
  frame_points_ = voxelDownsample(merged, p.voxel_size);
  frame_min_range_.assign(static_cast<std::size_t>(free_az_ * free_el_), INFINITY);
  frame_fine_min_range_.assign(static_cast<std::size_t>(az_bins_ * el_bins_), INFINITY);
  for (const auto& q : frame_points_) {
    const Eigen::Vector3f ray = q - sensor_origin_;
    const float r = ray.norm();
    const Angles a = anglesOf(ray);  // one pair of atan2 for both grids
    float& m = frame_min_range_[binOf(a, params_.tracks.free_bin_deg, free_az_, free_el_)];
    m = std::min(m, r);
    float& f = frame_fine_min_range_[binOf(a, params_.segmentation.free_space_bin_deg, az_bins_, el_bins_)];
    f = std::min(f, r);
  }
  for (const auto& q : frame_returns_) {
    const Eigen::Vector3f ray = q - sensor_origin_;
    float& f = frame_fine_min_range_[angularBin(ray)];
    f = std::min(f, ray.norm());
  }
}

void PerceptionNode::predictTracks(int64_t utime) {
  // All filters live at the time of the last processed frame; advance them to this one.
  const double dt = last_processed_utime_ > 0 ? seconds(utime - last_processed_utime_) : 0.0;
  last_processed_utime_ = utime;
  last_dt_ = dt;
  if (dt <= 0.0) return;
  for (auto& tr : tracks_) {
    if (tr.kf.predict(dt) != kalman::KalmanStatus::kOk) status_.count("kalman_errors");
  }
}

void PerceptionNode::segment() {
  const SegmentationParams& s = params_.segmentation;
  double t0 = stopwatch_();
  last_detections_.clear();
  point_moved_.assign(frame_points_.size(), 0);
  const auto groups = clusterer_.cluster(frame_points_, s.cluster_tolerance, s.min_cluster_points, s.max_cluster_points);
  status_.time("cluster", elapsedMs(t0));
  t0 = stopwatch_();
  const int64_t now = last_frame_utime_;
  // Reference frames of the motion test: old enough for a walking person to have moved.
  std::vector<const ProximityIndex*> refs;
  std::vector<const HistoryChunk*> ref_chunks;
  for (const auto& h : history_) {
    if (!h.closed || h.index.size() == 0) continue;
    if (seconds(now - h.last_utime) >= s.history_min_age && seconds(now - h.first_utime) <= s.history_max_age) {
      refs.push_back(&h.index);
      ref_chunks.push_back(&h);
    }
  }
  // The test needs (most of) the reference window: a partial one is too sparse (start-up).
  if (!ref_chunks.empty()) {
    const double covered = seconds(ref_chunks.back()->last_utime - ref_chunks.front()->first_utime);
    if (covered < 0.6 * (s.history_max_age - s.history_min_age)) {
      refs.clear();
      ref_chunks.clear();
    }
  }
  const Eigen::Vector2d robot = last_robot_xy_;
  const double support2 = s.track_support_distance * s.track_support_distance;
  const auto describe = [&](const std::vector<int>& g) {
    Detection d;
    d.indices = g;
    Eigen::Vector3f lo = frame_points_[g[0]], hi = lo;
    double zsum = 0.0;
    for (int i : g) {
      lo = lo.cwiseMin(frame_points_[i]);
      hi = hi.cwiseMax(frame_points_[i]);
      zsum += frame_points_[i].z();
    }
    d.box.center = viewCorrectedCenter(frame_points_, g, sensor_origin_.head<2>().cast<double>(), s.view_center_shift);
    d.box.size = (hi - lo).head<2>().cast<double>();
    d.min_z = lo.z();
    d.max_z = hi.z();
    d.mean_z = zsum / static_cast<double>(g.size());
    d.size_ok = d.box.size.maxCoeff() <= s.max_object_size && (d.max_z - d.min_z) >= s.min_object_height;
    if (d.size_ok) {
      for (const auto& tr : tracks_) {
        const Eigen::Vector2d p = tr.kf.state().head<2>();
        if ((p - d.box.center).squaredNorm() <= support2) {
          d.supported = true;
          break;
        }
      }
    }
    return d;
  };
  // FAPP-style motion test: marks the points of g with no reference point nearby that moved
  // (pointMoved); returns how many.
  const auto markMoved = [&](const std::vector<int>& g, const Eigen::Vector2d& center) {
    const double range = (center - robot).norm();
    const double dist = s.motion_distance + s.motion_distance_per_m * range;
    const auto motion_d2 = static_cast<float>(dist * dist);
    int moved = 0;
    for (int i : g) {
      bool near = false;
      for (const ProximityIndex* r : refs) {
        if (r->anyWithin(frame_points_[i], motion_d2)) {
          near = true;
          break;
        }
      }
      if (near) continue;
      const bool m = pointMoved(frame_points_[i], ref_chunks);
      moved += m ? 1 : 0;
      point_moved_[i] = m ? 1 : 0;
    }
    return moved;
  };
  for (const auto& g : groups) {
    Detection d = describe(g);
    if (d.size_ok && !refs.empty()) {
      d.moving = static_cast<double>(markMoved(g, d.box.center)) >= s.motion_ratio * static_cast<double>(g.size());
    } else if (!d.size_ok && !refs.empty() && d.box.size.maxCoeff() <= s.split_max_size &&
               (d.max_z - d.min_z) >= s.min_object_height) {
      // Too large for one object, small enough to be an object brushing a pillar or a box:
      // its moved points, clustered on their own, are the object (the rest stays structure).
      markMoved(g, d.box.center);
      Points moved_pts;
      std::vector<int> moved_idx;
      for (int i : g)
        if (point_moved_[i]) {
          moved_pts.push_back(frame_points_[i]);
          moved_idx.push_back(i);
        }
      if (static_cast<int>(moved_idx.size()) >= s.min_cluster_points) {
        for (const auto& c : clusterer_.cluster(moved_pts, s.cluster_tolerance, s.min_cluster_points, s.max_cluster_points)) {
          std::vector<int> idx;
          for (int k : c) idx.push_back(moved_idx[static_cast<std::size_t>(k)]);
          Detection part = describe(idx);
          if (!part.size_ok) continue;
          part.moving = true;
          status_.count("moving_parts_split");
          last_detections_.push_back(std::move(part));
        }
      }
    }
    last_detections_.push_back(std::move(d));
  }
  status_.time("motion", elapsedMs(t0));
}

bool PerceptionNode::pointMoved(const Eigen::Vector3f& p, const std::vector<const HistoryChunk*>& chunks) const {
  // A point with no reference point nearby is new surface. It is motion, not a disocclusion,
  // when some reference chunk (seen from its own sensor origin) either
  //  - saw past it along its ray: the space it occupies now was free (an object moving in), or
  //  - saw only nearer returns along its ray, and this frame sees through the farthest of
  //    them: what stood in front of the point then has gone (an object moving away; its new
  //    surface lies behind its old one, where the reference could not look).
  // Parallax from the robot's own motion fails both: the occluder is still there.
  // A direction no reference chunk looked in counts as moved (nothing was known to be there).
  // The vanishing test needs every chunk to have stopped short of the point: one ray of the
  // window passing beside a nearer edge in the same bin makes the bin ambiguous.
  const float margin = static_cast<float>(params_.segmentation.free_space_margin);
  float best_seen = 0.0f, best_range = 0.0f;
  const HistoryChunk* best = nullptr;
  for (const HistoryChunk* c : chunks) {
    const Eigen::Vector3f ray = p - c->origin;
    const float range = ray.norm();
    if (!(range > 0.0f)) continue;
    const float seen = c->max_range[static_cast<std::size_t>(angularBin(ray))];
    if (seen == 0.0f) continue;
    if (seen > range + margin) return true;
    if (best == nullptr || seen - range > best_seen - best_range) best = c, best_seen = seen, best_range = range;
  }
  if (best == nullptr) return true;
  if (best_seen >= best_range - margin) return false;
  // The gap bounds how far the object moved; a larger one is more likely structure revealed
  // by a mover that passed in front of it.
  if (best_seen < best_range - static_cast<float>(params_.segmentation.vanish_max_gap)) return false;
  const Eigen::Vector3f q = best->origin + (p - best->origin) * (best_seen / best_range) - sensor_origin_;
  const float now = frame_fine_min_range_[static_cast<std::size_t>(angularBin(q))];
  return std::isfinite(now) && now > q.norm() + margin;
}

std::vector<TrackView> PerceptionNode::trackViews(int64_t utime) const {
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

PerceptionNode::Measurement PerceptionNode::measure(const std::vector<int>& indices, const Track* track) const {
  Measurement m;
  if (indices.empty()) return m;
  Eigen::Vector3f lo = frame_points_[indices[0]], hi = lo;
  double zsum = 0.0;
  m.points.reserve(indices.size());
  for (int i : indices) {
    const auto& p = frame_points_[i];
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    zsum += p.z();
    m.points.push_back(p);
  }
  const Eigen::Vector2d sensor = sensor_origin_.head<2>().cast<double>();
  m.box.center = viewCorrectedCenter(frame_points_, indices, sensor, params_.segmentation.view_center_shift);
  m.box.size = (hi - lo).head<2>().cast<double>();
  m.size_z = hi.z() - lo.z();
  // Extent across the line of sight. A view cut on one side by something nearer (a pillar, a
  // person in front) has its centre pulled towards the visible side, and the differenced
  // velocity with it: with the track's width from uncut views, the centre is placed that
  // width from the visible edge instead.
  const Eigen::Vector2d view = m.box.center - sensor;
  if (view.norm() > 1e-6) {
    const Eigen::Vector2d u = view.normalized(), n(-u.y(), u.x());
    double b_lo = INFINITY, b_hi = -INFINITY;
    for (int i : indices) {
      const double b = n.dot(frame_points_[i].head<2>().cast<double>());
      b_lo = std::min(b_lo, b);
      b_hi = std::max(b_hi, b);
    }
    m.width = b_hi - b_lo;
    const double anchor = params_.segmentation.occlusion_anchor;
    if (track && anchor > 0.0) {
      const bool cut_lo = edgeOccluded(indices, n, false), cut_hi = edgeOccluded(indices, n, true);
      m.occluded = cut_lo || cut_hi;
      if (cut_lo != cut_hi && track->width > 0.0 && m.width < track->width - anchor) {
        const double b_mid = cut_hi ? b_lo + 0.5 * track->width : b_hi - 0.5 * track->width;
        m.box.center += n * (b_mid - 0.5 * (b_lo + b_hi));
        m.cut = true;
      }
    }
  }
  m.center << m.box.center, zsum / static_cast<double>(indices.size());
  return m;
}

bool PerceptionNode::edgeOccluded(const std::vector<int>& indices, const Eigen::Vector2d& n, bool hi) const {
  // The outermost points on that side, each looked past by one to three angular bins (turned
  // about the vertical towards that side; the bin's row and the rows above and below, a
  // frame's returns are sparse): a return nearer than the point by occlusion_margin there is
  // an occluder. A pillar a person brushes is not (it stands too close to the person), nor is
  // the ground (at a point's elevation it lies beyond the point).
  constexpr int kEdgePoints = 3, kSteps = 3;
  const auto margin = static_cast<float>(params_.segmentation.occlusion_margin);
  const double sign = hi ? 1.0 : -1.0;
  // The kEdgePoints largest (sign * n.p, index) pairs, largest first, without allocating.
  std::array<std::pair<double, int>, kEdgePoints> edge;
  int k = 0;
  for (int i : indices) {
    const std::pair<double, int> e(sign * n.dot(frame_points_[i].head<2>().cast<double>()), i);
    int at = k;
    while (at > 0 && (e.first > edge[at - 1].first || (e.first == edge[at - 1].first && e.second < edge[at - 1].second))) --at;
    if (at >= kEdgePoints) continue;
    for (int m = std::min(k, kEdgePoints - 1); m > at; --m) edge[m] = edge[m - 1];
    edge[at] = e;
    k = std::min(k + 1, kEdgePoints);
  }
  // +n is the line of sight turned anticlockwise: turning a ray anticlockwise looks past the hi side.
  const double bin = params_.segmentation.free_space_bin_deg * M_PI / 180.0;
  std::array<float, kSteps> cs, sn;
  for (int step = 1; step <= kSteps; ++step) {
    cs[step - 1] = static_cast<float>(std::cos(sign * bin * step));
    sn[step - 1] = static_cast<float>(std::sin(sign * bin * step));
  }
  for (int e = 0; e < k; ++e) {
    const Eigen::Vector3f ray = frame_points_[edge[e].second] - sensor_origin_;
    const float r = ray.norm();
    for (int step = 0; step < kSteps; ++step) {
      const float c = cs[step], s = sn[step];
      const Eigen::Vector3f turned(c * ray.x() - s * ray.y(), s * ray.x() + c * ray.y(), ray.z());
      const int b = angularBin(turned), az = b / el_bins_, el = b % el_bins_;
      for (int de = -1; de <= 1; ++de) {
        if (el + de < 0 || el + de >= el_bins_) continue;
        if (frame_fine_min_range_[static_cast<std::size_t>(az * el_bins_ + el + de)] < r - margin) return true;
      }
    }
  }
  return false;
}

double PerceptionNode::movedShare(const std::vector<int>& indices) const {
  if (indices.empty()) return 0.0;
  std::size_t n = 0;
  for (int i : indices) n += point_moved_[i] ? 1 : 0;
  return static_cast<double>(n) / static_cast<double>(indices.size());
}

std::vector<int> PerceptionNode::restrictToTrack(const Track& t, const std::vector<int>& indices) const {
  // A cluster much larger than the track's box is the object merged with something else (a
  // pillar it brushes, another person): measure only the points inside the track's predicted
  // box grown by the margin, if enough of them are there.
  const double margin = params_.tracks.merge_margin;
  Eigen::Vector2d lo = frame_points_[indices[0]].head<2>().cast<double>(), hi = lo;
  for (int i : indices) {
    lo = lo.cwiseMin(frame_points_[i].head<2>().cast<double>());
    hi = hi.cwiseMax(frame_points_[i].head<2>().cast<double>());
  }
  if (((hi - lo).array() <= (t.size.array() + margin)).all()) return indices;
  const Eigen::Vector2d c = t.kf.state().head<2>();
  const Eigen::Vector2d half = 0.5 * t.size + Eigen::Vector2d::Constant(0.5 * margin);
  std::vector<int> inside;
  for (int i : indices) {
    const Eigen::Vector2d d = (frame_points_[i].head<2>().cast<double>() - c).cwiseAbs();
    if ((d.array() <= half.array()).all()) inside.push_back(i);
  }
  // Of those, the points that moved (a pillar's do not), when there are enough.
  std::vector<int> moved;
  for (int i : inside)
    if (point_moved_[i]) moved.push_back(i);
  if (moved.size() >= 3) return moved;
  return inside.size() >= 3 ? inside : indices;
}

void PerceptionNode::applyMeasurement(Track& t, const Measurement& m, int64_t utime, int8_t how, bool moving) {
  const TrackParams& p = params_.tracks;
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
        status_.count("velocity_registered");
      }
    }
    st = t.kf.update(m.center, v);
  } else {
    st = t.kf.updatePosition(m.center);
  }
  if (st != kalman::KalmanStatus::kOk) {
    status_.count("kalman_errors");
    t.kf.init(m.center, Eigen::Vector3d::Zero());
  }
  t.measured.push_back({utime, m.center, std::move(points)});
  while (t.measured.size() > 2 && utime - t.measured[1].utime >= baseline_us) t.measured.pop_front();
  if (m.cut) status_.count("views_anchored");
  if (!m.occluded) {  // the width and box of a view cut by an occluder are not the object's
    t.size = (1.0 - p.size_smoothing) * t.size + p.size_smoothing * m.box.size;
    // Views missing a side without a visible occluder (sparse returns) are common, views wider
    // than the object are not: the width follows increases faster than decreases.
    const double w = m.width >= t.width ? p.size_smoothing : 0.25 * p.size_smoothing;
    t.width = t.width > 0.0 ? (1.0 - w) * t.width + w * m.width : m.width;
  }
  t.size_z = (1.0 - p.size_smoothing) * t.size_z + p.size_smoothing * m.size_z;
  t.history = thin(m.points, params_.reassociation.max_history_points);
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

void PerceptionNode::reidentify(Track& fresh, int64_t utime) {
  // The object a coasting track lost may come back as a new track (it turned while hidden,
  // or reappeared farther than the association gates): if the newly confirmed track is
  // where that object could have walked to since it was last seen, it takes over the
  // coasting track's identity, and the coasting track ends.
  const TrackParams& p = params_.tracks;
  if (p.reid_speed <= 0.0 || fresh.measured.empty()) return;
  const Eigen::Vector2d first = fresh.first_center;
  const auto score = [&](const Eigen::Vector2d& last, const Eigen::Vector2d& v, double dt) {
    return reidentificationScore(first, last, v, dt, p);
  };
  Track* best = nullptr;
  double best_d = 0.0;
  for (auto& tr : tracks_) {
    if (&tr == &fresh || tr.state != TO::STATE_COASTING || tr.measured.empty()) continue;
    if (tr.last_seen_utime > fresh.created_utime) continue;  // both seen at once: two objects
    const double dt = seconds(fresh.created_utime - tr.last_seen_utime);
    const Eigen::Vector2d last = tr.measured.back().center.head<2>();
    if ((first - last).norm() > p.reid_speed * dt + p.reid_margin) continue;
    const double d = score(last, tr.seen_velocity, dt);
    if (!best || d < best_d) best = &tr, best_d = d;
  }
  // Recently deleted confirmed tracks are candidates too (a coasting track may have been
  // seen through or timed out before its object came back).
  const LostTrack* best_lost = nullptr;
  for (const auto& l : lost_tracks_) {
    if (l.last_seen_utime > fresh.created_utime) continue;
    const double dt = seconds(fresh.created_utime - l.last_seen_utime);
    if ((first - l.last_center).norm() > p.reid_speed * dt + p.reid_margin) continue;
    const double d = score(l.last_center, l.seen_velocity, dt);
    if ((!best && !best_lost) || d < best_d) best_lost = &l, best = nullptr, best_d = d;
  }
  if (best) {
    fresh.id = best->id;
    fresh.age_frames = best->age_frames;
    best->state = TO::STATE_DELETED;
    best->reidentified = true;
  } else if (best_lost) {
    fresh.id = best_lost->id;
    fresh.age_frames = best_lost->age_frames;
    const int64_t id = best_lost->id;
    lost_tracks_.erase(std::remove_if(lost_tracks_.begin(), lost_tracks_.end(),
                                      [id](const LostTrack& l) { return l.id == id; }),
                       lost_tracks_.end());
  } else {
    return;
  }
  status_.count("reidentifications");
  (void)utime;
}

void PerceptionNode::manageTracks(int64_t utime, const std::vector<char>& updated) {
  const TrackParams& p = params_.tracks;
  for (std::size_t j = 0; j < updated.size(); ++j) {
    Track& tr = tracks_[j];
    ++tr.age_frames;
    if (updated[j]) {
      const double speed = tr.kf.state().segment<2>(3).norm();
      const double moved = tr.measured.empty() ? 0.0 : (tr.measured.back().center.head<2>() - tr.first_center).norm();
      if (tr.state == TO::STATE_TENTATIVE && tr.hits >= p.confirm_hits && speed >= p.confirm_min_speed &&
          speed <= p.confirm_max_speed && moved >= p.confirm_min_distance &&
          tr.moving_hits >= p.confirm_moving_hits) {
        tr.state = TO::STATE_CONFIRMED;
        tr.confirmed_once = true;
        status_.count("tracks_confirmed");
        reidentify(tr, utime);
      } else if (tr.state == TO::STATE_COASTING) {
        tr.state = TO::STATE_CONFIRMED;
      }
    } else {
      ++tr.misses;
      tr.num_points = 0;
      // Negative evidence: the sensor sees through where the track should be (the nearest
      // return in that direction lies well behind it), so the object is not there.
      {
        const Eigen::Vector3f ray = tr.kf.state().head<3>().cast<float>() - sensor_origin_;
        // The nearest return over the track's bin and its 8 neighbours: conservative, the
        // prediction may be a bin off and a few returns of the object itself keep it alive.
        float nearest = INFINITY;
        if (!frame_min_range_.empty()) {
          const int b = freeBin(ray), a0 = b / free_el_, e0 = b % free_el_;
          for (int da = -1; da <= 1; ++da)
            for (int de = -1; de <= 1; ++de) {
              const int a = (a0 + da + free_az_) % free_az_, e = e0 + de;
              if (e < 0 || e >= free_el_) continue;
              nearest = std::min(nearest, frame_min_range_[static_cast<std::size_t>(a * free_el_ + e)]);
            }
        }
        const bool seen_through = std::isfinite(nearest) && nearest > ray.norm() + static_cast<float>(p.free_margin);
        tr.free_count = seen_through ? tr.free_count + 1 : 0;
        if (tr.free_count >= p.free_frames) tr.state = TO::STATE_DELETED;
      }
      // Unseen objects (people) stop and turn more often than they keep straight on: let the
      // coasting velocity decay instead of extrapolating it at full speed. The covariance
      // keeps growing through the filter's own prediction.
      if (p.coast_velocity_decay > 0.0 && last_dt_ > 0.0) {
        kalman::State6 x = tr.kf.state();
        x.tail<3>() *= std::exp(-last_dt_ / p.coast_velocity_decay);
        if (tr.kf.initState(x, tr.kf.covariance()) != kalman::KalmanStatus::kOk) status_.count("kalman_errors");
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
    if (seconds(utime - tr.last_moving_utime) > p.max_stationary ||
        seconds(utime - std::max(tr.last_fast_utime, tr.created_utime)) > p.max_stationary)
      tr.state = TO::STATE_DELETED;
  }
  // Deleted confirmed tracks are remembered for re-identification for a while.
  for (const auto& tr : tracks_) {
    if (tr.state != TO::STATE_DELETED || tr.reidentified || tr.confirmed_once == false || tr.measured.empty()) continue;
    lost_tracks_.push_back(
        {tr.id, tr.age_frames, tr.measured.back().center.head<2>(), tr.seen_velocity, tr.last_seen_utime});
  }
  while (!lost_tracks_.empty() && seconds(utime - lost_tracks_.front().last_seen_utime) > p.reid_window)
    lost_tracks_.pop_front();
  const auto before = tracks_.size();
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [](const Track& tr) { return tr.state == TO::STATE_DELETED; }),
                tracks_.end());
  status_.count("tracks_deleted", static_cast<int64_t>(before - tracks_.size()));
}

tracked_objects_t PerceptionNode::buildObjects(int64_t utime, int64_t frame_seq) const {
  tracked_objects_t o{};
  o.utime = utime;
  o.seq = objects_seq_;
  o.valid = true;
  o.frame_seq = frame_seq;
  o.frame_id = "world";
  for (const auto& tr : tracks_) {
    TO t{};
    t.id = tr.id;
    t.state = tr.state;
    t.last_association = tr.last_association;
    const auto& x = tr.kf.state();
    t.x = x(0);
    t.y = x(1);
    t.z = x(2);
    t.vx = x(3);
    t.vy = x(4);
    t.vz = x(5);
    t.cov_size = 36;
    t.cov.resize(36);
    const auto& P = tr.kf.covariance();
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) t.cov[static_cast<std::size_t>(r * 6 + c)] = P(r, c);
    t.size_x = std::max(tr.size.x(), 0.01);
    t.size_y = std::max(tr.size.y(), 0.01);
    t.size_z = std::max(tr.size_z, 0.01);
    t.yaw = 0.0;
    t.num_points = tr.num_points;
    t.age_frames = tr.age_frames;
    t.frames_since_seen = tr.misses;
    o.objects.push_back(std::move(t));
  }
  o.num_objects = static_cast<int32_t>(o.objects.size());
  return o;
}

static_points_t PerceptionNode::buildStatic(int64_t utime, const Eigen::Isometry3d& T,
                                            const std::vector<char>& dynamic_point) const {
  static_points_t s{};
  s.utime = utime;
  s.seq = static_seq_;
  s.valid = true;
  const Eigen::Vector3d& origin = sensor_origin_d_;  // this frame's, world frame
  s.origin_x = origin.x();
  s.origin_y = origin.y();
  s.origin_z = origin.z();
  s.max_range = static_cast<float>(params_.preprocess.max_range);
  for (std::size_t i = 0; i < frame_points_.size(); ++i) {
    if (dynamic_point[i]) continue;
    s.x.push_back(frame_points_[i].x());
    s.y.push_back(frame_points_[i].y());
    s.z.push_back(frame_points_[i].z());
  }
  s.num_points = static_cast<int32_t>(s.x.size());
  return s;
}

int PerceptionNode::freeBin(const Eigen::Vector3f& d) const {
  return binOf(anglesOf(d), params_.tracks.free_bin_deg, free_az_, free_el_);
}

int PerceptionNode::angularBin(const Eigen::Vector3f& d) const {
  return binOf(anglesOf(d), params_.segmentation.free_space_bin_deg, az_bins_, el_bins_);
}

void PerceptionNode::pushHistory(int64_t utime, const std::vector<char>& tracked_point) {
  const SegmentationParams& sp = params_.segmentation;
  const int64_t chunk_us = static_cast<int64_t>(sp.history_chunk * 1e6);
  if (history_.empty() || history_.back().closed) {
    history_.emplace_back();
    history_.back().first_utime = utime;
  }
  HistoryChunk& c = history_.back();
  if (c.max_range.empty()) {
    c.origin = sensor_origin_;
    c.max_range.assign(static_cast<std::size_t>(az_bins_ * el_bins_), 0.0f);
  }
  // Free-space evidence of the newest frame: every return, ground included (frame_points_
  // holds the last frames again, cropped).
  for (const auto& p : frame_returns_) {
    const Eigen::Vector3f ray = p - c.origin;
    float& m = c.max_range[angularBin(ray)];
    m = std::max(m, ray.norm());
  }
  c.last_utime = utime;
  // Reference points: what this frame did not give to a track. Someone walking where a tracked
  // person was (a follower, or the person itself turning back) would otherwise be matched
  // against that trail and look static. Free-space evidence above
  // still includes it, so structure wrongly tracked for a moment is not taken for motion.
  if (sp.history_static_only) {
    for (std::size_t i = 0; i < frame_points_.size(); ++i)
      if (!tracked_point[i]) c.points.push_back(frame_points_[i]);
  } else {
    c.points.insert(c.points.end(), frame_points_.begin(), frame_points_.end());
  }
  if (utime - c.first_utime >= chunk_us) {
    c.index.build(c.points);
    c.points.clear();
    c.points.shrink_to_fit();
    c.closed = true;
  }
  const int64_t keep_us = static_cast<int64_t>(sp.history_max_age * 1e6);
  while (!history_.empty() && utime - history_.front().first_utime > keep_us) history_.pop_front();
  ++objects_seq_;
  ++static_seq_;
}

}  // namespace perception
}  // namespace ucon
