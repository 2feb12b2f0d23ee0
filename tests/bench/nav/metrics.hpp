#pragma once
/// @file metrics.hpp
/// What a bench nav run measures: the mission in the loop (goals out; success, collisions and
/// what was hit; tracking recall and velocity error against the ground truth), the result of
/// one run, and the per-density rows of the table.

#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "probes.hpp"
#include "ucon/mission/mission_node.hpp"
#include "ucon/mot/clear_mot.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/world/world.hpp"

namespace ucon::bench::nav {

extern const char* const kStages[];  ///< "driver", "perception", "planner", "controller"
constexpr int kNumStages = 4;

/// How soon perception holds a mover that comes into view near the robot. An arrival starts at
/// the first ground-truth step at which a mover is within kRange of the robot and in view
/// (kHiddenVisibility) after a step at which it was not (hidden, farther away, or not yet seen),
/// with no track within kTrackDistance of it; it ends when such a track appears (its delay is
/// recorded) or, missed, when the mover leaves view or range first. A mover a track already holds
/// as it comes into view (a coasting track taking it back) is no arrival; one still open when
/// the run ends is not counted.
class AcquisitionTally {
 public:
  static constexpr double kRange = 6.0;          // [m]
  static constexpr double kTrackDistance = 0.5;  // [m]
  /// One ground-truth step of one mover: whether it is within kRange and in view, and whether a
  /// track lies within kTrackDistance of it.
  void step(int64_t utime, int64_t id, bool near_in_view, bool tracked);
  const std::vector<double>& delays() const { return delays_; }  ///< of the arrivals tracked [s]
  int64_t missed() const { return missed_; }

 private:
  struct Mover {
    bool was_in = false, open = false;
    int64_t since = 0;
  };
  std::map<int64_t, Mover> movers_;
  std::vector<double> delays_;
  int64_t missed_ = 0;
};

/// Velocity errors against the std the tracks state, summed: n samples, Σ |v error|^2 and Σ the
/// trace of the stated velocity covariance (pooled over runs with merge()).
struct VelocitySums {
  double err2_sum = 0.0, var_sum = 0.0;
  int64_t n = 0;
  void add(double err2, double var) { err2_sum += err2, var_sum += var, ++n; }
  void merge(const VelocitySums& o) { err2_sum += o.err2_sum, var_sum += o.var_sum, n += o.n; }
  double rmsError() const { return n ? std::sqrt(err2_sum / double(n)) : NAN; }
  double errorOverStd() const { return var_sum > 0.0 ? std::sqrt(err2_sum / var_sum) : NAN; }
};

/// The tracking quality near the robot, summed over a run's ground-truth steps.
struct TrackingTally {
  int64_t recall_total = 0, recall_hit = 0;  ///< visible movers within 10 m; those with a track within 0.7 m
  double verr_sum = 0.0;                     ///< Σ |v_track - v_mover| of the tracked movers within 5 m [m/s]
  int64_t verr_n = 0;
  double verr2_sum = 0.0, vvar_sum = 0.0;    ///< Σ |v error|^2 and Σ the trace of the stated velocity covariance
  /// The same over the tracks at most kYoungFrames frames old (0.3 s at 50 Hz): a track's first
  /// velocities, when a mover just came into view near the robot.
  VelocitySums young;
  static constexpr int kYoungFrames = 15;
  AcquisitionTally acquisition;               ///< movers coming into view within 6 m
  /// Ground-truth steps of movers within kCloseRange of the robot closing in faster than
  /// kCloseSpeed, and those of them whose mover was inside a static obstacle within
  /// kInsideWindowUs before (counted only with a world): how common what the collision report's
  /// hitThroughStatic() says is, away from collisions.
  int64_t close_total = 0, close_through_static = 0;
  static constexpr double kCloseRange = 3.0, kCloseSpeed = 0.5;  ///< [m], [m/s]
  static constexpr int64_t kInsideWindowUs = 2'000'000;
  double recall() const { return recall_total ? double(recall_hit) / double(recall_total) : NAN; }
  double velocityError() const { return verr_n ? verr_sum / double(verr_n) : NAN; }
  double velocityErrorOverStd() const { return vvar_sum > 0.0 ? std::sqrt(verr2_sum / vvar_sum) : NAN; }
};

/// How perception held the mover a run collided with, over the second before the hit (0.3 s
/// and less before it cannot change the outcome): hidden from the sensor at some sample (less
/// than kHiddenVisibility of its silhouette in view: no perception could have held it then),
/// else never a track within 1.5 m, a track within 0.2 m and 0.35 m/s of the mover at every
/// sample, or anything between (late, off, coasting away, a wrong velocity after a switch).
enum class HitTracking { kNone, kHidden, kUntracked, kTrackedPoorly, kTrackedWell };
const char* toString(HitTracking h);
/// One sample of the mover hit: its visibility (NaN: not computed), whether a track lay within
/// 1.5 m, its distance [m] and the size of its velocity error [m/s].
struct HitSample {
  bool tracked = false;
  double offset = NAN, velocity_error = NAN;
  double visible = NAN;
};
/// kNone without samples.
HitTracking classifyHitTracking(const std::vector<HitSample>& samples);

/// The smallest gap [m] between a disc (centre x, y, `radius`) and the footprints of `world`'s
/// static obstacles (< 0: the disc overlaps one; infinity without static obstacles). The bench
/// worlds' movers walk through static obstacles (bench_generator.hpp), unseen while inside one.
double staticGap(const world::World& world, double x, double y, double radius);

/// The mission in the loop: ROBOT_POSE and SIM_GROUND_TRUTH in, NAV_GOAL out (the scenario's
/// goals in order, re-sent every resend_period_s until reached, as ucon-mission does). Also
/// tallies the tracking quality and, at the first collision, reports what was hit.
class MissionAdapter : public rp::NodeAdapter {
 public:
  /// `world`: the run's world, for the collision report (whether the mover hit came out of a
  /// static obstacle); null: not reported. It must outlive the adapter.
  MissionAdapter(const mission::MissionParams& p, std::vector<Eigen::Vector2d> goals, double timeout_s,
                 const world::World* world = nullptr)
      : node_(p, std::move(goals), timeout_s), world_(world) {}

  std::string name() const override { return "mission"; }
  std::vector<std::string> inputChannels() const override;
  std::vector<std::string> outputChannels() const override;
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {{"goals_sent", goals_sent_}}; }
  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override;

  bool reachedAll() const { return reached_all_; }
  bool collided() const { return collided_; }
  /// "mover <id> (...) ...; <plan>" or "static; <plan>", then the mover's history before the hit.
  const std::string& collisionWith() const { return collision_with_; }
  const std::string& history() const { return history_; }
  bool hitMover() const { return hit_mover_; }
  HitTracking hitTracking() const { return hit_tracking_; }
  /// The mover hit overlapped a static obstacle within the 2 s before the hit
  /// (TrackingTally::kInsideWindowUs; needs `world`).
  bool hitThroughStatic() const { return hit_through_static_; }
  double robotSpeedAtHit() const { return robot_speed_at_hit_; }
  bool timedOut() const { return node_.done() && !reached_all_; }
  mission::MissionSummary summary() const { return node_.summary(); }
  const TrackingTally& tracking() const { return tracking_; }
  /// CLEAR-MOT of every PERCEPTION_OBJECTS until the first collision against the ground truth
  /// nearest in time (within 50 ms): every mover within kMotRange of the robot, matched within
  /// kMotThreshold (bench worlds compute no visibility: hidden movers count as misses).
  mot::ClearMotSummary clearMot() const { return mot_.summary(); }
  static constexpr double kMotRange = 15.0;     ///< [m] perception's crop range
  static constexpr double kMotThreshold = 1.0;  ///< [m] as bench perception

 private:
  void onGroundTruth(const sim_ground_truth_t& m);
  void tallyTracking(const sim_ground_truth_t& m);
  void scoreObjects(const tracked_objects_t& objects);
  void reportCollision(const sim_ground_truth_t& m);
  /// One line per 0.25 s before the hit: the mover and robot as they were, the nearest track.
  std::string moverHistory(int64_t id) const;
  /// The mover's nearest track over the snapshots 1.0-0.3 s before the last one.
  HitTracking moverTracking(int64_t id) const;

  /// Whether mover `id` overlapped a static obstacle within TrackingTally::kInsideWindowUs
  /// before `now` [us] (as recorded by tallyTracking()).
  bool insideStaticWithin(int64_t id, int64_t now) const;

  mission::MissionNode node_;
  const world::World* world_ = nullptr;
  /// Per mover within kInsideRange of the robot: the last ground-truth time its body overlapped a
  /// static obstacle [us] (with a world only).
  std::map<int64_t, int64_t> inside_static_utime_;
  static constexpr double kInsideRange = 8.0;  ///< [m]
  bool reached_all_ = false, collided_ = false, hit_mover_ = false, hit_through_static_ = false;
  HitTracking hit_tracking_ = HitTracking::kNone;
  TrackingTally tracking_;
  mot::ClearMotAccumulator mot_;
  std::string collision_with_;
  tracked_objects_t last_objects_;
  std::string last_plan_;
  struct Snapshot {
    sim_ground_truth_t gt;
    tracked_objects_t tracks;
    std::string plan;
    std::shared_ptr<const std::vector<uint8_t>> statics;  ///< PERCEPTION_STATIC as published
  };
  std::shared_ptr<const std::vector<uint8_t>> last_static_;
  std::deque<Snapshot> recent_;
  std::string history_;
  double robot_speed_at_hit_ = NAN;
  int64_t goals_sent_ = 0;
};

/// One run of one world.
struct RunResult {
  int n_dynamic = 0;
  uint64_t seed = 0;
  bool ok = false;  ///< the run could be set up
  std::string error;
  bool success = false, collision = false, timeout = false;
  double time_to_goal_s = NAN;
  double sim_s = 0.0, wall_s = 0.0, cpu_s = 0.0;
  double wait_s = 0.0;  ///< wall time the loop's thread waited for the worker threads (pipelined)
  double min_clearance = NAN;
  std::string collision_with;  ///< "mover <id> (<speed>)" or "static"; empty if none seen on ground truth
  bool hit_mover = false;
  HitTracking hit_tracking = HitTracking::kNone;  ///< of the mover hit (MissionAdapter::hitTracking())
  bool hit_through_static = false;  ///< MissionAdapter::hitThroughStatic()
  std::string plan_tally;  ///< " fallbacks k=n ...": the planner's counters of what it did when a plan failed its check
  double robot_speed_at_hit = NAN;
  double dist_start_goal = 0.0, dist_left = 0.0;
  double dist_from_start = 0.0;  ///< where the robot ended, from its start [m]
  std::map<std::string, int64_t> messages;
  int64_t wheel_cmds_applied = 0;
  int64_t leaked_static = 0, static_points = 0;
  int64_t close_total = 0, close_through_static = 0;  ///< TrackingTally's
  double velocity_error = NAN;  ///< mean |v_track - v_mover| [m/s] of tracked movers within 5 m of the robot
  double velocity_error_over_std = NAN;  ///< rms of that error / rms of the velocity std the tracks state
  double recall = NAN;  ///< share of visible movers within 10 m with a track within 0.7 m
  VelocitySums young;  ///< TrackingTally::young
  std::vector<double> acquire_s;  ///< AcquisitionTally::delays() [s]
  int64_t acquire_missed = 0;     ///< AcquisitionTally::missed()
  mot::ClearMotSummary mot;  ///< MissionAdapter::clearMot()
  StageTimes stages[kNumStages];
  /// Faults injected (--faults): deliveries lost, late, lost to a killed node (inputs and outputs
  /// in flight), restarts.
  int64_t faults_dropped = 0, faults_delayed = 0, faults_killed = 0, faults_restarts = 0;
  /// True (and why) when the run shows that the pipeline itself is broken.
  bool pipelineBroken(std::string* why) const;
};

/// The planner's counters of what it did when a plan failed its check, as " fallbacks k=n ...".
std::string planTally(const std::vector<std::pair<std::string, int64_t>>& planner_counters);

/// One density's runs together (a line of the table).
struct Row {
  int n_dynamic = 0;
  std::string model;  ///< the planner's obstacle model (--planner-model)
  int runs = 0, successes = 0, collisions = 0, timeouts = 0;
  std::vector<double> ttg;
  double sim_s = 0.0, wall_s = 0.0, cpu_s = 0.0, wait_s = 0.0;
  int hit_mover = 0, hit_static = 0;
  int hit_hidden = 0, hit_untracked = 0, hit_tracked_poorly = 0, hit_tracked_well = 0;  ///< collisions with movers by HitTracking
  int hit_through_static = 0;  ///< collisions with movers that were inside a static obstacle within 2 s before
  int64_t close_total = 0, close_through_static = 0;  ///< every run's TrackingTally counts, summed
  std::vector<double> recall, verr, vcons;  // per run
  VelocitySums young;                       // every run's young tracks, pooled
  std::vector<double> acquire_s;            // every run's acquisition delays, pooled [s]
  int64_t acquire_missed = 0;               // arrivals that left view or range untracked
  /// Arrivals (AcquisitionTally) of all runs, and those tracked within `s` seconds.
  int64_t acquireArrivals() const { return static_cast<int64_t>(acquire_s.size()) + acquire_missed; }
  int64_t acquiredWithin(double s) const;
  std::vector<double> mota, idsw, fn_rate, fp_rate, motp;  // per run (CLEAR-MOT)
  std::vector<double> samples[kNumStages];
  double stage_total_ms[kNumStages] = {0, 0, 0, 0};
  std::map<std::string, double> by_input_ms[kNumStages];
  void add(const RunResult& r);
};

}  // namespace ucon::bench::nav
