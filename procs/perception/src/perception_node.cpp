#include "ucon/perception/perception_node.hpp"

#include <algorithm>
#include <chrono>

#include "ucon/perception/outputs.hpp"
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

tracked_object_t messageOf(const Track& tr) {
  ObjectEstimate e;
  e.id = tr.id;
  e.state = tr.state;
  e.last_association = tr.last_association;
  e.x = tr.kf.state();
  e.P = tr.kf.covariance();
  e.size << tr.size, tr.size_z;
  e.num_points = tr.num_points;
  e.age_frames = tr.age_frames;
  e.frames_since_seen = tr.misses;
  return toMessage(e);
}

}  // namespace

/// Per track that existed before the frame: the points that measure it and how they were
/// found; per detection whether it is taken; per frame point whether a track has it.
struct PerceptionNode::Assignment {
  Assignment(std::size_t n_tracks, std::size_t n_detections, std::size_t n_points)
      : points(n_tracks),
        how(n_tracks, TO::ASSOC_NONE),
        moving(n_tracks, 0),
        taken(n_detections, 0),
        tracked_point(n_points, 0) {}
  std::vector<std::vector<int>> points;  ///< per track: the frame points of its measurement
  std::vector<int8_t> how;               ///< per track: tracked_object_t::ASSOC_*
  std::vector<char> moving;              ///< per track: its measured points passed the motion test
  std::vector<char> taken;               ///< per detection: matched, or recovered objects' (no new track)
  std::vector<char> tracked_point;       ///< per frame point: it measures or starts a track
};

PerceptionNode::PerceptionNode(const PerceptionParams& params, Stopwatch stopwatch)
    : params_(params),
      stopwatch_(stopwatch ? std::move(stopwatch) : Stopwatch(steadySeconds)),
      poses_(2.0),
      status_("perception"),
      fine_grid_(params.segmentation.free_space_bin_deg),
      coarse_grid_(params.tracks.free_bin_deg),
      preprocessor_(params.preprocess, fine_grid_, coarse_grid_),
      motion_(params.segmentation, fine_grid_),
      detector_(params.segmentation),
      measurer_(params.segmentation, fine_grid_),
      tracks_(params, coarse_grid_),
      persistence_(params.segmentation.static_cell, params.segmentation.static_persistence,
                   params.segmentation.static_max_gap) {
  // Counters exist from the start so the status always lists them.
  for (const char* c : {"frames_in", "frames_processed", "frames_repeated", "frames_out_of_order",
                        "frames_bad_utime", "frames_malformed", "frames_bad_frame_id", "frames_empty",
                        "frames_no_pose", "frames_stale_pose", "frames_pose_extrapolated", "lidar_timeouts",
                        "points_in", "points_non_finite",
                        "poses_in", "poses_invalid", "poses_non_finite", "poses_out_of_order",
                        "tracks_created", "tracks_confirmed", "tracks_deleted", "reassociations",
                        "kalman_errors", "invalid_outputs", "reidentifications", "moving_parts_split",
                        "views_anchored", "velocity_registered", "structure_declined", "clusters_split",
                        "static_cells_held", "tracks_started_returning"})
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
  out.objects = invalidObjects(utime, objects_seq_++, frame_seq);
  out.static_points = invalidStatic(utime, static_seq_++, params_.preprocess.max_range);
  last_output_utime_ = utime;
  status_.count("invalid_outputs");
  status_.setHealth(process_status_t::HEALTH_WARN, why);
  return out;
}

bool PerceptionNode::onStructure(const std::vector<int>& points, int64_t since) const {
  // The cells as of the previous frame (this frame's hits are recorded after the tracks'
  // update), occupied without a gap since structure_margin before `since`: an object holds a
  // cell for a moment as it walks over it, and may have stood a moment where it was when its
  // track started or came to its place. Cells come from the static persistence test, so the
  // rule is off with it (segmentation.static_persistence 0).
  const TrackParams& p = params_.tracks;
  if (p.structure_frames <= 0 || points.empty()) return false;
  const int64_t before = since - static_cast<int64_t>(p.structure_margin * 1e6);
  std::size_t old = 0;
  for (int i : points) {
    const Eigen::Vector3f& q = frame_.points[static_cast<std::size_t>(i)];
    const int64_t t = persistence_.occupiedSince(q.x(), q.y(), frame_.utime);
    old += t != CellAge::kNever && t < before ? 1 : 0;
  }
  return static_cast<double>(old) >= p.structure_share * static_cast<double>(points.size());
}

PerceptionOutput PerceptionNode::tick(int64_t utime) {
  if (utime <= 0) return {};
  const int64_t last = std::max(last_frame_utime_, last_output_utime_);
  if (utime - last <= static_cast<int64_t>(params_.frame_timeout * 1e6)) return {};
  status_.count("lidar_timeouts");  // LIDAR_POINTS stale: one per frame_timeout without a frame
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

  // 1. Pre-processing.
  double t = stopwatch_();
  const Preprocessor::Result pre = preprocessor_.process(cloud, *pose, poses_, params_.pose_max_gap, &frame_);
  if (pre.non_finite) status_.count("points_non_finite", pre.non_finite);
  if (pre.pose_extrapolated) status_.count("frames_pose_extrapolated");
  status_.time("preprocess", elapsedMs(t));

  // 2. Clustering, motion test, support from the tracks' predictions.
  t = stopwatch_();
  tracks_.predict(utime, status_);
  double t_stage = stopwatch_();
  detector_.cluster(frame_);
  status_.time("cluster", elapsedMs(t_stage));
  t_stage = stopwatch_();
  motion_.selectReference(utime);
  int split_parts = 0;
  detections_ = detector_.classify(&frame_, motion_, tracks_.predictedCenters(), &split_parts);
  if (split_parts > 0) status_.count("moving_parts_split", split_parts);
  status_.time("motion", elapsedMs(t_stage));
  status_.time("segment", elapsedMs(t));

  // 3. Object-level association.
  t = stopwatch_();
  std::vector<int> dynamic;  // detection indices that are dynamic
  for (int i = 0; i < static_cast<int>(detections_.size()); ++i)
    if (detections_[i].dynamic()) dynamic.push_back(i);
  const std::vector<TrackView> views = tracks_.views(utime);
  const std::size_t n_old_tracks = tracks_.tracks().size();
  Assignment a(n_old_tracks, detections_.size(), frame_.points.size());
  associate(dynamic, views, &a);
  status_.time("associate", elapsedMs(t));

  // 4. Point-level historical re-association of the tracks left unmatched, then every
  // measured track's filter update.
  t = stopwatch_();
  if (params_.useUcon() && params_.reassociation.enabled) recover(dynamic, views, &a);
  std::vector<char> updated(n_old_tracks, 0);
  for (std::size_t j = 0; j < n_old_tracks; ++j) {
    if (a.how[j] == TO::ASSOC_NONE || a.points[j].empty()) continue;
    const Track& tr = tracks_.tracks()[j];
    const bool on_structure = tr.state != TO::STATE_TENTATIVE && onStructure(a.points[j], tr.arrival_utime);
    // A coasting track near structure keeps the structure's cluster dynamic by its own
    // prediction (segmentation.track_support_distance); taking it would pull the track onto the
    // box beside which it lost its person, and the structure rule would end it before the
    // person came out again.
    if (on_structure && !a.moving[j] && tr.state == TO::STATE_COASTING && params_.tracks.structure_decline) {
      tracks_.declineOnStructure(j);
      status_.count("structure_declined");
      continue;
    }
    const Measurement m = measurer_.measure(frame_, a.points[j], tr.width);
    tracks_.update(j, m, utime, a.how[j], a.moving[j] != 0, on_structure, status_);
    updated[j] = 1;
    for (int i : a.points[j]) a.tracked_point[i] = 1;
  }
  status_.time("reassociate", elapsedMs(t));

  // 5. Track management: the lifecycle, then new tracks from unmatched moving clusters.
  t = stopwatch_();
  tracks_.manage(utime, updated, frame_, status_);
  startTracks(dynamic, &a);
  status_.time("track", elapsedMs(t));

  // 6. Outputs; the frame joins the motion test's history.
  PerceptionOutput out;
  std::vector<tracked_object_t> objects;
  objects.reserve(tracks_.tracks().size());
  for (const auto& tr : tracks_.tracks()) objects.push_back(messageOf(tr));
  out.objects = objectsMessage(utime, objects_seq_, cloud.seq, std::move(objects));
  std::vector<char> not_static = a.tracked_point;  // + points whose cell is not persistent yet
  t = stopwatch_();
  if (params_.segmentation.static_persistence > 0.0) {
    StaticPersistence::Occlusion hidden;
    hidden.origin = frame_.sensor_origin;
    hidden.grid = &fine_grid_;
    hidden.nearest = &frame_.nearest_fine;
    hidden.margin = static_cast<float>(params_.segmentation.free_space_margin);
    hidden.max_range = static_cast<float>(params_.preprocess.max_range);
    hidden.max_hidden = params_.segmentation.static_hold_max;
    const int64_t held = persistence_.holds();
    persistence_.update(utime, frame_.points, &persistent_,
                        params_.segmentation.static_hold_max > 0.0 ? &hidden : nullptr, &a.tracked_point);
    if (persistence_.holds() > held) status_.count("static_cells_held", persistence_.holds() - held);
    for (std::size_t i = 0; i < frame_.points.size(); ++i)
      if (!persistent_[i]) not_static[i] = 1;
  }
  status_.time("persistence", elapsedMs(t));
  out.static_points = staticMessage(utime, static_seq_, frame_.sensor_origin_d, params_.preprocess.max_range,
                                    frame_.points, not_static);
  t = stopwatch_();
  motion_.push(frame_, a.tracked_point);
  status_.time("history", elapsedMs(t));
  ++objects_seq_;
  ++static_seq_;
  last_output_utime_ = utime;

  int confirmed = 0;
  for (const auto& tr : tracks_.tracks()) confirmed += tr.state == TO::STATE_CONFIRMED || tr.state == TO::STATE_COASTING;
  status_.set("tracks", static_cast<double>(tracks_.tracks().size()));
  status_.set("tracks_confirmed", confirmed);
  status_.set("points_per_frame", static_cast<double>(frame_.points.size()));
  status_.set("detections", static_cast<double>(detections_.size()));
  status_.set("dynamic_detections", static_cast<double>(dynamic.size()));
  status_.setHealth(process_status_t::HEALTH_OK, "");
  last_frame_ms_ = elapsedMs(t_start);
  status_.time("total", last_frame_ms_);
  return out;
}

void PerceptionNode::associate(const std::vector<int>& dynamic, const std::vector<TrackView>& views, Assignment* a) {
  std::vector<DetectionView> dviews;
  dviews.reserve(dynamic.size());
  for (int i : dynamic) dviews.push_back({detections_[i].box});
  const Matching match = params_.useUcon()
                             ? associateObjects(dviews, views, params_.paper.mu, params_.object_association)
                             : associateNearest(dviews, views, params_.object_association);
  for (std::size_t k = 0; k < dynamic.size(); ++k) {
    const int j = match.detection_to_track[k];
    if (j < 0) continue;
    const Track& tr = tracks_.tracks()[j];
    const std::vector<int>& indices = detections_[dynamic[k]].indices;
    a->taken[dynamic[k]] = 1;
    const std::vector<int> sharing = sharingTracks(indices, j, match, views);
    if (sharing.empty()) {
      a->points[j] = restrictToTrack(frame_.points, frame_.moved, tr.kf.state().head<2>(), tr.size,
                                     params_.tracks.merge_margin, indices);
      a->how[j] = TO::ASSOC_OBJECT;
      a->moving[j] = movedShare(frame_.moved, a->points[j]) >= params_.segmentation.motion_ratio;
      continue;
    }
    // Objects merged into one cluster: each point measures the track predicted nearest to it
    // (a part too small to measure leaves its track to re-association).
    std::vector<int> owners = sharing;
    owners.push_back(j);
    std::vector<Eigen::Vector2d> centers;
    for (int o : owners) centers.push_back(views[o].box.center);
    std::vector<std::vector<int>> parts = splitByNearest(frame_.points, indices, centers);
    status_.count("clusters_split");
    for (std::size_t s = 0; s < owners.size(); ++s) {
      const int o = owners[s];
      if (parts[s].size() < 3 || (o != j && a->how[o] != TO::ASSOC_NONE)) continue;
      a->points[o] = std::move(parts[s]);
      a->how[o] = TO::ASSOC_OBJECT;
      a->moving[o] = movedShare(frame_.moved, a->points[o]) >= params_.segmentation.motion_ratio;
    }
  }
}

std::vector<int> PerceptionNode::sharingTracks(const std::vector<int>& indices, int j, const Matching& match,
                                               const std::vector<TrackView>& views) const {
  // Tracks followed up to the last frame (not tentative, seen within cascade_after, velocity
  // settled) that took no cluster of their own and whose prediction lies in this cluster's x-y
  // bounds (grown by kShareMargin): their objects merged with track j's.
  constexpr double kShareMargin = 0.1;  // [m]
  std::vector<int> sharing;
  if (!params_.useUcon() || !params_.object_association.split_shared || indices.empty()) return sharing;
  // The split places each point by the predictions: a track whose velocity is not settled yet
  // (a young one) would take the wrong half.
  const auto settled = [&](std::size_t t) { return velocitySettled(tracks_.tracks()[t], params_.kalman.velocity_std); };
  if (!settled(static_cast<std::size_t>(j))) return sharing;
  Eigen::Vector2d lo = frame_.points[indices[0]].head<2>().cast<double>(), hi = lo;
  for (int i : indices) {
    lo = lo.cwiseMin(frame_.points[i].head<2>().cast<double>());
    hi = hi.cwiseMax(frame_.points[i].head<2>().cast<double>());
  }
  for (std::size_t o = 0; o < views.size(); ++o) {
    if (static_cast<int>(o) == j || match.track_to_detection[o] >= 0) continue;
    if (tracks_.tracks()[o].state == TO::STATE_TENTATIVE || views[o].since_last > params_.object_association.cascade_after ||
        !settled(o))
      continue;
    const Eigen::Vector2d c = views[o].box.center;
    if ((c.array() >= lo.array() - kShareMargin).all() && (c.array() <= hi.array() + kShareMargin).all())
      sharing.push_back(static_cast<int>(o));
  }
  return sharing;
}

void PerceptionNode::recover(const std::vector<int>& dynamic, const std::vector<TrackView>& views, Assignment* a) {
  // Tentative tracks are not recovered: a duplicate would steal its original's points.
  std::vector<std::size_t> lost_index;
  std::vector<LostTrack> lost;
  for (std::size_t j = 0; j < a->how.size(); ++j) {
    const Track& tr = tracks_.tracks()[j];
    if (a->how[j] != TO::ASSOC_NONE || tr.state == TO::STATE_TENTATIVE || tr.history.empty() ||
        tr.consecutive_reassoc >= params_.reassociation.max_consecutive)
      continue;
    lost_index.push_back(j);
    lost.push_back({{tr.history, tr.kf.state().tail<3>(), seconds(frame_.utime - tr.last_seen_utime)}, views[j]});
  }
  if (lost.empty() || frame_.points.empty()) return;
  // P is every pre-processed point of the frame: the environment, the unmatched clusters and
  // the matched ones (an object merged into another object's cluster or into static structure
  // is found there).
  frame_index_.build(frame_.points, params_.paper.d0);  // only frames with a lost track need it
  std::vector<const std::vector<int>*> matched;
  for (std::size_t j = 0; j < a->how.size(); ++j)
    if (a->how[j] == TO::ASSOC_OBJECT) matched.push_back(&a->points[j]);
  Recovery r = recoverLostTracks(lost, frame_.points, frame_index_, matched,
                                 frame_.sensor_origin.head<2>().cast<double>(), params_);
  for (std::size_t k = 0; k < lost.size(); ++k) {
    if (r.points[k].empty()) continue;
    a->points[lost_index[k]] = std::move(r.points[k]);
    a->how[lost_index[k]] = TO::ASSOC_REASSOCIATED;
    status_.count("reassociations");
  }
  // An unmatched cluster mostly taken by recovered objects is theirs: no new track.
  for (int i : dynamic) {
    if (a->taken[i] || !mostlyClaimed(detections_[i].indices, r.claimed)) continue;
    a->taken[i] = 1;
    for (int p : detections_[i].indices) a->tracked_point[p] = 1;
  }
}

void PerceptionNode::startTracks(const std::vector<int>& dynamic, Assignment* a) {
  for (int i : dynamic) {
    const Detection& d = detections_[i];
    if (a->taken[i] || !d.moving) continue;
    // A fragment of an object already tracked (or its re-detection right beside it) does not
    // start a second track.
    if (tracks_.nearTrack(d.box.center)) continue;
    if (!tracks_.start(measurer_.measure(frame_, d.indices), frame_.utime, status_)) continue;
    for (int p : d.indices) a->tracked_point[p] = 1;
  }
}

}  // namespace perception
}  // namespace ucon
