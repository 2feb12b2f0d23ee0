#include "metrics.hpp"

#include <algorithm>
#include <cstdio>

#include "ucon/channels.hpp"
#include "ucon/mot/runtime_frames.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/trajectory_t.hpp"

namespace ucon::bench::nav {

const char* const kStages[] = {"driver", "perception", "planner", "controller"};

namespace {

const sim_object_t* moverById(const sim_ground_truth_t& gt, int64_t id) {
  const sim_object_t* o = nullptr;
  for (const auto& c : gt.objects)
    if (c.id == id) o = &c;
  return o;
}

/// The track nearest to (x, y) and its distance (INFINITY without one).
const tracked_object_t* nearestTrack(const tracked_objects_t& tracks, double x, double y, double* distance) {
  const tracked_object_t* tr = nullptr;
  *distance = INFINITY;
  for (const auto& t : tracks.objects) {
    const double d = std::hypot(t.x - x, t.y - y);
    if (d < *distance) *distance = d, tr = &t;
  }
  return tr;
}

}  // namespace

std::vector<std::string> MissionAdapter::inputChannels() const {
  return {channels::kRobotPose, channels::kSimGroundTruth, channels::kPerceptionObjects, channels::kPerceptionStatic,
          channels::kPlannerTrajectory};
}

std::vector<std::string> MissionAdapter::outputChannels() const { return {channels::kNavGoal}; }

rp::FeedResult MissionAdapter::feed(const std::string& channel, const uint8_t* data, std::size_t size,
                                    std::vector<rp::OutputMessage>* out) {
  if (channel == channels::kPerceptionObjects) {
    // Scored, and kept to say at a collision whether perception tracked what was hit.
    if (collided_) return rp::FeedResult::kHandled;
    if (!rp::decodeExact(data, size, &last_objects_)) return rp::FeedResult::kDecodeError;
    scoreObjects(last_objects_);
    return rp::FeedResult::kHandled;
  }
  if (channel == channels::kPerceptionStatic) {
    // Kept as bytes (decoded only for a collision report): static points on the mover hit.
    if (!collided_) last_static_ = std::make_shared<const std::vector<uint8_t>>(data, data + size);
    return rp::FeedResult::kHandled;
  }
  if (channel == channels::kPlannerTrajectory) {
    trajectory_t t;
    if (!rp::decodeExact(data, size, &t)) return rp::FeedResult::kDecodeError;
    if (!collided_) last_plan_ = "plan status " + std::to_string(int(t.status)) + (t.message.empty() ? "" : " (" + t.message + ")");
    return rp::FeedResult::kHandled;
  }
  if (channel == channels::kRobotPose) {
    robot_pose_t m;
    if (!rp::decodeExact(data, size, &m)) return rp::FeedResult::kDecodeError;
    if (auto g = node_.onPose(m)) {
      out->push_back(rp::encodeOutput(channels::kNavGoal, *g));
      ++goals_sent_;
    }
    const auto s = node_.summary();
    reached_all_ = s.goals_total > 0 && s.goals_reached == s.goals_total;
    return rp::FeedResult::kHandled;
  }
  if (channel == channels::kSimGroundTruth) {
    sim_ground_truth_t m;
    if (!rp::decodeExact(data, size, &m)) return rp::FeedResult::kDecodeError;
    onGroundTruth(m);
    return rp::FeedResult::kHandled;
  }
  return rp::FeedResult::kIgnored;
}

void MissionAdapter::scoreObjects(const tracked_objects_t& objects) {
  // The ground truth nearest in time, from the snapshots kept for the collision report.
  const sim_ground_truth_t* g = nullptr;
  int64_t best = 50'000;  // [us]
  for (auto it = recent_.rbegin(); it != recent_.rend() && it->gt.utime >= objects.utime - best; ++it) {
    const int64_t dt = std::abs(it->gt.utime - objects.utime);
    if (dt <= best) best = dt, g = &it->gt;
  }
  if (g == nullptr) return;
  mot::RuntimeEvalOptions eval;
  eval.threshold_m = kMotThreshold;
  eval.max_range_m = kMotRange;
  mot_.updateXY(mot::groundTruthAt(*g, objects.utime, eval), mot::hypothesesOf(objects, eval), eval.threshold_m);
}

void MissionAdapter::onGroundTruth(const sim_ground_truth_t& m) {
  node_.onGroundTruth(m);
  // The last 2 s of ground truth with the tracks of the time, for the collision report.
  if (!collided_) {
    recent_.push_back({m, last_objects_, last_plan_, last_static_});
    if (recent_.size() > 100) recent_.pop_front();
  }
  tallyTracking(m);
  if (!collided_ && (m.collision || m.num_collisions > 0)) reportCollision(m);
  collided_ = collided_ || m.collision || m.num_collisions > 0;
}

void AcquisitionTally::step(int64_t utime, int64_t id, bool near_in_view, bool tracked) {
  Mover& m = movers_[id];
  if (near_in_view && !m.was_in && !tracked) {
    m.open = true;
    m.since = utime;
  } else if (near_in_view && m.open && tracked) {
    delays_.push_back(1e-6 * static_cast<double>(utime - m.since));
    m.open = false;
  } else if (!near_in_view && m.open) {
    ++missed_;
    m.open = false;
  }
  m.was_in = near_in_view;
}

void MissionAdapter::tallyTracking(const sim_ground_truth_t& m) {
  for (const auto& o : m.objects) {
    const double range = std::hypot(o.x - m.robot_x, o.y - m.robot_y);
    // The nearest track, looked up once for both tallies (acquisition within 6 m, recall 10 m).
    double td = INFINITY;
    const tracked_object_t* nearest = range <= 10.0 ? nearestTrack(last_objects_, o.x, o.y, &td) : nullptr;
    tracking_.acquisition.step(m.utime, o.id, range <= AcquisitionTally::kRange && o.visible >= kHiddenVisibility,
                               td < AcquisitionTally::kTrackDistance);
    if (world_ != nullptr && range <= kInsideRange) {
      if (staticGap(*world_, o.x, o.y, o.radius) < 0.0) inside_static_utime_[o.id] = m.utime;
      const double rx = o.x - m.robot_x, ry = o.y - m.robot_y;
      const double closing = -((o.vx - m.robot_vx) * rx + (o.vy - m.robot_vy) * ry) / std::max(range, 1e-6);
      if (range <= TrackingTally::kCloseRange && closing > TrackingTally::kCloseSpeed) {
        ++tracking_.close_total;
        tracking_.close_through_static += insideStaticWithin(o.id, m.utime) ? 1 : 0;
      }
    }
    if (o.visible < kHiddenVisibility || range > 10.0) continue;  // NaN: not computed, counted
    ++tracking_.recall_total;
    const tracked_object_t* near = td < 0.7 ? nearest : nullptr;
    if (near) {
      ++tracking_.recall_hit;
      // Velocity error of the tracks of movers within 5 m: what the planner predicts with.
      if (range < 5.0) {
        tracking_.verr_sum += std::hypot(near->vx - o.vx, near->vy - o.vy);
        ++tracking_.verr_n;
        if (near->cov.size() == 36) {  // the velocity block's trace is E|v_err|^2 if the track is right
          const double e2 = (near->vx - o.vx) * (near->vx - o.vx) + (near->vy - o.vy) * (near->vy - o.vy);
          const double var = near->cov[3 * 6 + 3] + near->cov[4 * 6 + 4];
          tracking_.verr2_sum += e2;
          tracking_.vvar_sum += var;
          if (near->age_frames <= TrackingTally::kYoungFrames) tracking_.young.add(e2, var);
        }
      }
    }
  }
}

void MissionAdapter::reportCollision(const sim_ground_truth_t& m) {
  // What was hit: the nearest mover if the robot touches it, else a static obstacle.
  double best = INFINITY;
  const sim_object_t* hit = nullptr;
  for (const auto& o : m.objects) {
    const double gap = std::hypot(o.x - m.robot_x, o.y - m.robot_y) - o.radius - m.robot_radius;
    if (gap < best) {
      best = gap;
      hit = &o;
    }
  }
  char buf[256];
  std::string inside_note;
  if (hit && best < 0.05) {
    // The track nearest to the mover, if any: was it seen, and how well?
    double td = INFINITY;
    const tracked_object_t* tr = nearestTrack(last_objects_, hit->x, hit->y, &td);
    char trk[128];
    if (tr && td < 1.0)
      std::snprintf(trk, sizeof(trk), "tracked %.2f m off, v err %.2f m/s, state %d", td,
                    std::hypot(tr->vx - hit->vx, tr->vy - hit->vy), int(tr->state));
    else
      std::snprintf(trk, sizeof(trk), "NOT tracked (nearest track %.1f m)", td);
    std::snprintf(buf, sizeof(buf), "mover %lld (%.2f m/s, r %.2f) %s; %s", static_cast<long long>(hit->id),
                  std::hypot(hit->vx, hit->vy), hit->radius, trk, last_plan_.c_str());
    history_ = moverHistory(hit->id);
    hit_tracking_ = moverTracking(hit->id);
    hit_mover_ = true;
    hit_through_static_ = insideStaticWithin(hit->id, m.utime);
    if (hit_through_static_) {
      char b[96];
      std::snprintf(b, sizeof(b), " [inside a static obstacle %.2f s before]",
                    1e-6 * static_cast<double>(m.utime - inside_static_utime_.at(hit->id)));
      inside_note = b;
    }
  } else {
    std::snprintf(buf, sizeof(buf), "static; %s", last_plan_.c_str());
  }
  collision_with_ = buf;
  if (hit_mover_) collision_with_ += std::string(" [in the second before: ") + toString(hit_tracking_) + "]" + inside_note;
  robot_speed_at_hit_ = std::hypot(m.robot_vx, m.robot_vy);
}

bool MissionAdapter::insideStaticWithin(int64_t id, int64_t now) const {
  const auto it = inside_static_utime_.find(id);
  return it != inside_static_utime_.end() && now - it->second <= TrackingTally::kInsideWindowUs;
}

double staticGap(const world::World& world, double x, double y, double radius) {
  return world.staticContact(world::Vec2(x, y), radius).clearance;
}

const char* toString(HitTracking h) {
  switch (h) {
    case HitTracking::kNone: return "none";
    case HitTracking::kHidden: return "hidden";
    case HitTracking::kUntracked: return "untracked";
    case HitTracking::kTrackedPoorly: return "tracked poorly";
    case HitTracking::kTrackedWell: return "tracked well";
  }
  return "?";
}

HitTracking classifyHitTracking(const std::vector<HitSample>& samples) {
  if (samples.empty()) return HitTracking::kNone;
  bool any = false, all_well = true;
  for (const auto& s : samples)
    if (s.visible < kHiddenVisibility) return HitTracking::kHidden;  // NaN: not computed
  for (const auto& s : samples) {
    any = any || s.tracked;
    all_well = all_well && s.tracked && s.offset < 0.2 && s.velocity_error < 0.35;
  }
  return !any ? HitTracking::kUntracked : all_well ? HitTracking::kTrackedWell : HitTracking::kTrackedPoorly;
}

HitTracking MissionAdapter::moverTracking(int64_t id) const {
  if (recent_.empty()) return HitTracking::kNone;
  const int64_t t_hit = recent_.back().gt.utime;
  std::vector<HitSample> samples;
  for (const Snapshot& s : recent_) {
    const int64_t before = t_hit - s.gt.utime;
    if (before > 1'000'000 || before < 300'000) continue;
    const sim_object_t* o = moverById(s.gt, id);
    if (!o) continue;
    HitSample h;
    h.visible = o->visible;
    const tracked_object_t* tr = nearestTrack(s.tracks, o->x, o->y, &h.offset);
    h.tracked = tr != nullptr && h.offset < 1.5;
    if (h.tracked) h.velocity_error = std::hypot(tr->vx - o->vx, tr->vy - o->vy);
    samples.push_back(h);
  }
  return classifyHitTracking(samples);
}

std::string MissionAdapter::moverHistory(int64_t id) const {
  std::string out;
  for (std::size_t k = 0; k < recent_.size(); k += 12) {
    const Snapshot& s = recent_[k];
    const sim_object_t* o = moverById(s.gt, id);
    if (!o) continue;
    double td = INFINITY;
    const tracked_object_t* tr = nearestTrack(s.tracks, o->x, o->y, &td);
    int on_body = 0;  // static points published on the mover's body (a ghost the map keeps)
    static_points_t statics{};
    if (s.statics && rp::decodeExact(s.statics->data(), s.statics->size(), &statics))
      for (int q = 0; q < statics.num_points; ++q)
        on_body += std::hypot(statics.x[q] - o->x, statics.y[q] - o->y) < o->radius + 0.1 ? 1 : 0;
    char b[360];
    const double gap = std::hypot(o->x - s.gt.robot_x, o->y - s.gt.robot_y) - o->radius - s.gt.robot_radius;
    if (tr && td < 1.5)
      std::snprintf(b, sizeof(b), "\n    t-%.2fs gap %.2f m robot v (%.2f %.2f) mover at (%.2f %.2f) v (%.2f %.2f) r %.2f vis %.2f static %d | track %lld %.2f m off v (%.2f %.2f) r %.2f st %d assoc %d pts %d | %s",
                    1e-6 * double(recent_.back().gt.utime - s.gt.utime), gap, s.gt.robot_vx, s.gt.robot_vy, o->x, o->y, o->vx, o->vy,
                    o->radius, o->visible, on_body, static_cast<long long>(tr->id), td, tr->vx, tr->vy,
                    0.5 * std::hypot(tr->size_x, tr->size_y), int(tr->state),
                    int(tr->last_association), tr->num_points, s.plan.substr(0, 60).c_str());
    else
      std::snprintf(b, sizeof(b), "\n    t-%.2fs gap %.2f m robot v (%.2f %.2f) mover at (%.2f %.2f) v (%.2f %.2f) vis %.2f static %d | no track | %s",
                    1e-6 * double(recent_.back().gt.utime - s.gt.utime), gap, s.gt.robot_vx, s.gt.robot_vy, o->x, o->y, o->vx, o->vy,
                    o->visible, on_body, s.plan.substr(0, 60).c_str());
    out += b;
  }
  return out;
}


bool RunResult::pipelineBroken(std::string* why) const {
  auto count = [&](const char* ch) {
    auto it = messages.find(ch);
    return it == messages.end() ? int64_t{0} : it->second;
  };
  if (!ok) return *why = error, true;
  if (count(channels::kLidarPoints) == 0) return *why = "no LIDAR_POINTS frames", true;
  if (count(channels::kPerceptionObjects) == 0) return *why = "no PERCEPTION_OBJECTS", true;
  if (count(channels::kPlannerTrajectory) == 0) return *why = "no PLANNER_TRAJECTORY", true;
  if (wheel_cmds_applied == 0) return *why = "no wheel command reached the plant", true;
  // A robot that detoured and was hit before it got closer to its goal still drove: only one
  // that ended within 1 m of its start without getting 1 m closer never moved.
  if (dist_start_goal - dist_left < 1.0 && dist_from_start < 1.0)
    return *why = "the robot did not get 1 m closer to its goal, nor 1 m from its start", true;
  return false;
}

std::string planTally(const std::vector<std::pair<std::string, int64_t>>& planner_counters) {
  static const std::map<std::string, std::string> kShown{
      {"result_kept_previous", "kept"},       {"result_stop_no_feasible", "stop"},
      {"least_bad_plans", "least_bad"},       {"evasive_plans", "evasive"},
      {"evasive_manoeuvres", "manoeuvre"},    {"evasion_kept", "evasion_kept"},
      {"rejected_limit_violation", "rejected_limits"}, {"rejected_dynamic_collision", "rejected_mover"},
      {"rejected_static_collision", "rejected_static"}};
  std::string tally;
  for (const auto& [k, n] : planner_counters) {
    const auto it = kShown.find(k);
    if (it != kShown.end() && n > 0) tally += (tally.empty() ? " fallbacks " : " ") + it->second + "=" + std::to_string(n);
  }
  return tally;
}

int64_t Row::acquiredWithin(double s) const {
  return std::count_if(acquire_s.begin(), acquire_s.end(), [s](double d) { return d <= s; });
}

void Row::add(const RunResult& r) {
  ++runs;
  successes += r.success;
  collisions += r.collision;
  timeouts += r.timeout;
  if (r.success) ttg.push_back(r.time_to_goal_s);
  sim_s += r.sim_s;
  wall_s += r.wall_s;
  cpu_s += r.cpu_s;
  wait_s += r.wait_s;
  if (r.collision) (r.hit_mover ? hit_mover : hit_static) += 1;
  if (r.collision && r.hit_mover) {
    hit_hidden += r.hit_tracking == HitTracking::kHidden;
    hit_untracked += r.hit_tracking == HitTracking::kUntracked;
    hit_tracked_poorly += r.hit_tracking == HitTracking::kTrackedPoorly;
    hit_tracked_well += r.hit_tracking == HitTracking::kTrackedWell;
    hit_through_static += r.hit_through_static;
  }
  close_total += r.close_total;
  close_through_static += r.close_through_static;
  if (std::isfinite(r.recall)) recall.push_back(r.recall);
  acquire_s.insert(acquire_s.end(), r.acquire_s.begin(), r.acquire_s.end());
  acquire_missed += r.acquire_missed;
  if (std::isfinite(r.velocity_error)) verr.push_back(r.velocity_error);
  if (std::isfinite(r.velocity_error_over_std)) vcons.push_back(r.velocity_error_over_std);
  young.merge(r.young);
  if (r.mot.num_objects > 0) {
    mota.push_back(r.mot.mota);
    idsw.push_back(static_cast<double>(r.mot.num_switches));
    fn_rate.push_back(r.mot.fn_rate);
    fp_rate.push_back(r.mot.fp_rate);
    if (std::isfinite(r.mot.motp)) motp.push_back(r.mot.motp);
  }
  for (int k = 0; k < kNumStages; ++k) {
    samples[k].insert(samples[k].end(), r.stages[k].samples_ms.begin(), r.stages[k].samples_ms.end());
    stage_total_ms[k] += r.stages[k].total_ms;
    for (const auto& [ch, ms] : r.stages[k].by_input_ms) by_input_ms[k][ch] += ms;
  }
}

}  // namespace ucon::bench::nav
