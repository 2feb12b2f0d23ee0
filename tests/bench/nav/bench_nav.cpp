// ucon-bench-nav: the whole navigation stack in-process and in lock step (issue 8). Per run:
// the Simulator emulates the Mid-360 (Livox UDP datagrams, as the live simulator sends them),
// the lidar driver node parses them and assembles point frames, then perception, planner and
// base controller nodes run through their replay adapters on a zero-latency bus
// (ucon::replay::recordSimulatedRun, the same loop as ucon-sim-record); BASE_WHEEL_CMD drives
// the simulator's Mecanum plant. The mission (ucon::mission::MissionNode, as in `deploy/ucon
// sim`) sends the scenario's goals on NAV_GOAL. Time is simulation utime only; the wall clock
// only measures stage latencies and the speed relative to real time.
//
// A run succeeds when every goal is reached within the timeout with no collision; it stops at
// the goal, at the first collision or at the timeout. Prints a table and writes JSON
// {"results": [{"n_dynamic", "runs", "success_rate", "collisions", "time_to_goal_s",
//               "realtime_factor", "tracking_recall", "velocity_error_mps", "velocity_error_over_std",
//               "latency_ms": {"driver", "perception", "planner", "controller"}}]}
// (tracking_recall: median over runs of the share of visible movers within 10 m with a track
// within 0.7 m; velocity_error_mps: median over runs of the mean |v_track - v_mover| of those
// within 5 m of the robot; velocity_error_over_std: median over runs of the rms of that error over
// the rms of the standard deviation the track states for it, 1 for a consistent covariance).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/cpu_time.hpp"
#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/mission/mission_node.hpp"
#include "ucon/perception/outputs.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/replay/sim_recorder.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/simulator/scenario_loader.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory_t.hpp"
#include "../bench_util.hpp"
#include "odometry_in_loop.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

namespace {

using ucon::bench::percentile;
using ucon::bench::split;

namespace rp = ucon::replay;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string num(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6g", x);
  return buf;
}

const char* const kStages[] = {"driver", "perception", "planner", "controller"};
constexpr int kNumStages = 4;

/// Wall time of one stage: every call (total) and the calls that are one unit of the stage's
/// work (samples: a frame for the driver and perception, a plan for the planner, a control
/// tick for the controller).
struct StageTimes {
  std::vector<double> samples_ms;
  double total_ms = 0.0;
  std::map<std::string, double> by_input_ms;  ///< total per input channel (nodes only)
};

/// Times a node's feed() (decode, handlers, ticks, encode; the consumers of its outputs run
/// after feed() returns, so they are not included).
class TimedAdapter : public rp::NodeAdapter {
 public:
  /// `unit_channel`: a feed whose outputs include this channel (or, if `on_input`, a feed of
  /// this channel) is one sample.
  TimedAdapter(rp::NodeAdapter* inner, StageTimes* times, std::string unit_channel, bool on_input)
      : inner_(inner), times_(times), unit_(std::move(unit_channel)), on_input_(on_input) {}

  std::string name() const override { return inner_->name(); }
  std::vector<std::string> inputChannels() const override { return inner_->inputChannels(); }
  std::vector<std::string> outputChannels() const override { return inner_->outputChannels(); }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return inner_->counters(); }
  double helperCpuSeconds() const override { return inner_->helperCpuSeconds(); }

  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override {
    const std::size_t before = out->size();
    const auto t0 = Clock::now();
    const rp::FeedResult r = inner_->feed(channel, data, size, out);
    const double ms = msSince(t0);
    times_->total_ms += ms;
    times_->by_input_ms[channel] += ms;
    bool unit = on_input_ && channel == unit_;
    for (std::size_t i = before; !on_input_ && i < out->size(); ++i) unit = unit || (*out)[i].channel == unit_;
    if (unit) times_->samples_ms.push_back(ms);
    return r;
  }

 private:
  rp::NodeAdapter* inner_;
  StageTimes* times_;
  std::string unit_;
  bool on_input_;
};

/// Diagnosis: wraps (timed) perception. Always counts PERCEPTION_STATIC points that lie on a
/// mover's body (the leak). --oracle-objects drops its PERCEPTION_OBJECTS and publishes the
/// simulator's ground-truth movers in range instead (exact position and velocity, small fixed
/// covariance); --oracle-velocity keeps perception's tracks but gives each the velocity of the
/// ground-truth mover within 0.8 m of it; --oracle-static removes from PERCEPTION_STATIC every
/// point within 0.25 m of a mover's body. Runs then show what planning and control do with
/// perfect tracking (or perfect velocities) and/or a static map that movers never pollute.
class OracleObjectsAdapter : public rp::NodeAdapter {
 public:
  OracleObjectsAdapter(rp::NodeAdapter* inner, double range, bool replace_objects, bool clean_static,
                       bool true_velocity)
      : inner_(inner),
        range_(range),
        replace_objects_(replace_objects),
        clean_static_(clean_static),
        true_velocity_(true_velocity) {}
  std::string name() const override { return inner_->name(); }
  std::vector<std::string> inputChannels() const override {
    auto v = inner_->inputChannels();
    v.push_back(ucon::channels::kSimGroundTruth);
    return v;
  }
  std::vector<std::string> outputChannels() const override { return inner_->outputChannels(); }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return inner_->counters(); }
  double helperCpuSeconds() const override { return inner_->helperCpuSeconds(); }
  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override {
    if (channel != ucon::channels::kSimGroundTruth) {
      const std::size_t before = out->size();
      const rp::FeedResult r = inner_->feed(channel, data, size, out);
      if (replace_objects_)
        out->erase(std::remove_if(out->begin() + static_cast<std::ptrdiff_t>(before), out->end(),
                                  [](const rp::OutputMessage& m) { return m.channel == ucon::channels::kPerceptionObjects; }),
                   out->end());
      for (std::size_t i = before; i < out->size(); ++i) {
        auto& m = (*out)[i];
        if (true_velocity_ && m.channel == ucon::channels::kPerceptionObjects) {
          ucon::tracked_objects_t o;
          if (!rp::decodeExact(m.data.data(), m.data.size(), &o)) continue;
          for (auto& t : o.objects) {
            const ucon::sim_object_t* best = nullptr;
            double best_d = 0.8;
            for (const auto& g : last_gt_.objects) {
              const double d = std::hypot(g.x - t.x, g.y - t.y);
              if (d < best_d) best_d = d, best = &g;
            }
            if (best != nullptr) t.vx = best->vx, t.vy = best->vy;
          }
          m = rp::encodeOutput(ucon::channels::kPerceptionObjects, o);
          continue;
        }
        if (m.channel != ucon::channels::kPerceptionStatic || last_gt_.objects.empty()) continue;
        ucon::static_points_t s;
        if (!rp::decodeExact(m.data.data(), m.data.size(), &s)) continue;
        // Leak: static points on a mover's body (within 0.1 m of its surface), movers within
        // 15 m of the robot. Each such point paints a ghost obstacle into the planner's map.
        {
          // Squared distances, movers first cut to the cloud's bounding box: this probe runs on
          // perception's thread and must not slow the pipeline down.
          float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
          for (int k = 0; k < s.num_points; ++k) {
            x0 = std::min(x0, s.x[k]), x1 = std::max(x1, s.x[k]);
            y0 = std::min(y0, s.y[k]), y1 = std::max(y1, s.y[k]);
          }
          struct Disc {
            float x, y, r2;
          };
          std::vector<Disc> near_movers;
          for (const auto& g : last_gt_.objects) {
            const float reach = static_cast<float>(g.radius + 0.1);
            if (std::hypot(g.x - last_gt_.robot_x, g.y - last_gt_.robot_y) >= 15.0 || g.x + reach < x0 ||
                g.x - reach > x1 || g.y + reach < y0 || g.y - reach > y1)
              continue;
            near_movers.push_back({static_cast<float>(g.x), static_cast<float>(g.y), reach * reach});
          }
          for (int k = 0; k < s.num_points && !near_movers.empty(); ++k)
            for (const auto& g : near_movers) {
              const float dx = s.x[k] - g.x, dy = s.y[k] - g.y;
              if (dx * dx + dy * dy < g.r2) {
                ++leaked_points_;
                break;
              }
            }
          static_points_ += s.num_points;
        }
        if (clean_static_) {
          ucon::static_points_t c = s;
          c.x.clear(), c.y.clear(), c.z.clear();
          for (int k = 0; k < s.num_points; ++k) {
            bool near = false;
            for (const auto& g : last_gt_.objects)
              near = near || std::hypot(s.x[k] - g.x, s.y[k] - g.y) < g.radius + 0.25;
            if (near) continue;
            c.x.push_back(s.x[k]), c.y.push_back(s.y[k]), c.z.push_back(s.z[k]);
          }
          c.num_points = static_cast<int32_t>(c.x.size());
          m = rp::encodeOutput(ucon::channels::kPerceptionStatic, c);
        }
      }
      return r;
    }
    ucon::sim_ground_truth_t& g = last_gt_;
    if (!rp::decodeExact(data, size, &g)) return rp::FeedResult::kDecodeError;
    if (!replace_objects_) return rp::FeedResult::kHandled;
    std::vector<ucon::tracked_object_t> objects;
    for (const auto& s : g.objects) {
      if (std::hypot(s.x - g.robot_x, s.y - g.robot_y) > range_) continue;
      ucon::perception::ObjectEstimate e;  // confirmed, measured at object level
      e.id = s.id;
      e.x << s.x, s.y, 0.5 * s.height, s.vx, s.vy, 0.0;
      e.P.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 0.1 * 0.1, 0.1 * 0.1, 0.1 * 0.1;
      e.size << 2.0 * s.radius, 2.0 * s.radius, s.height;
      e.num_points = 10;
      e.age_frames = 100;
      objects.push_back(ucon::perception::toMessage(e));
    }
    out->push_back(rp::encodeOutput(ucon::channels::kPerceptionObjects,
                                    ucon::perception::objectsMessage(g.utime, seq_++, -1, std::move(objects))));
    return rp::FeedResult::kHandled;
  }

 private:
  rp::NodeAdapter* inner_;
  double range_;
  bool replace_objects_, clean_static_, true_velocity_;
 public:
  int64_t leaked_points_ = 0, static_points_ = 0;

 private:
  ucon::sim_ground_truth_t last_gt_;
  int64_t seq_ = 0;
};

/// The mission in the loop: ROBOT_POSE and SIM_GROUND_TRUTH in, NAV_GOAL out (the scenario's
/// goals in order, re-sent every resend_period_s until reached, as ucon-mission does).
class MissionAdapter : public rp::NodeAdapter {
 public:
  MissionAdapter(const ucon::mission::MissionParams& p, std::vector<Eigen::Vector2d> goals, double timeout_s)
      : node_(p, std::move(goals), timeout_s) {}

  std::string name() const override { return "mission"; }
  std::vector<std::string> inputChannels() const override {
    return {ucon::channels::kRobotPose, ucon::channels::kSimGroundTruth, ucon::channels::kPerceptionObjects,
            ucon::channels::kPerceptionStatic, ucon::channels::kPlannerTrajectory};
  }
  std::vector<std::string> outputChannels() const override { return {ucon::channels::kNavGoal}; }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {{"goals_sent", goals_sent_}}; }

  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override {
    if (channel == ucon::channels::kPerceptionObjects) {
      // Kept only to say, at a collision, whether perception tracked what was hit.
      if (!collided_ && !rp::decodeExact(data, size, &last_objects_)) return rp::FeedResult::kDecodeError;
      return rp::FeedResult::kHandled;
    }
    if (channel == ucon::channels::kPerceptionStatic) {
      // Kept as bytes (decoded only for a collision report): static points on the mover hit.
      if (!collided_) last_static_ = std::make_shared<const std::vector<uint8_t>>(data, data + size);
      return rp::FeedResult::kHandled;
    }
    if (channel == ucon::channels::kPlannerTrajectory) {
      ucon::trajectory_t t;
      if (!rp::decodeExact(data, size, &t)) return rp::FeedResult::kDecodeError;
      if (!collided_) last_plan_ = "plan status " + std::to_string(int(t.status)) + (t.message.empty() ? "" : " (" + t.message + ")");
      return rp::FeedResult::kHandled;
    }
    if (channel == ucon::channels::kRobotPose) {
      ucon::robot_pose_t m;
      if (!rp::decodeExact(data, size, &m)) return rp::FeedResult::kDecodeError;
      if (auto g = node_.onPose(m)) {
        out->push_back(rp::encodeOutput(ucon::channels::kNavGoal, *g));
        ++goals_sent_;
      }
      const auto s = node_.summary();
      reached_all_ = s.goals_total > 0 && s.goals_reached == s.goals_total;
    } else if (channel == ucon::channels::kSimGroundTruth) {
      ucon::sim_ground_truth_t m;
      if (!rp::decodeExact(data, size, &m)) return rp::FeedResult::kDecodeError;
      node_.onGroundTruth(m);
      // The last 2 s of ground truth with the tracks of the time, for the collision report.
      if (!collided_) {
        recent_.push_back({m, last_objects_, last_plan_, last_static_});
        if (recent_.size() > 100) recent_.pop_front();
      }
      // Tracking recall near the robot: movers within 10 m (and visible, where the simulator says)
      // with a track within 0.7 m.
      for (const auto& o : m.objects) {
        if (o.visible <= 0.3 || std::hypot(o.x - m.robot_x, o.y - m.robot_y) > 10.0) continue;  // NaN: not computed
        ++recall_total_;
        const ucon::tracked_object_t* near = nullptr;
        double nd = 0.7;
        for (const auto& t : last_objects_.objects) {
          const double d = std::hypot(t.x - o.x, t.y - o.y);
          if (d < nd) nd = d, near = &t;
        }
        if (near) {
          ++recall_hit_;
          // Velocity error of the tracks of movers within 5 m: what the planner predicts with.
          if (std::hypot(o.x - m.robot_x, o.y - m.robot_y) < 5.0) {
            verr_sum_ += std::hypot(near->vx - o.vx, near->vy - o.vy);
            ++verr_n_;
            if (near->cov.size() == 36) {  // the velocity block's trace is E|v_err|^2 if the track is right
              verr2_sum_ += (near->vx - o.vx) * (near->vx - o.vx) + (near->vy - o.vy) * (near->vy - o.vy);
              vvar_sum_ += near->cov[3 * 6 + 3] + near->cov[4 * 6 + 4];
            }
          }
        }
      }
      if (!collided_ && (m.collision || m.num_collisions > 0)) {
        // What was hit: the nearest mover if the robot touches it, else a static obstacle.
        double best = INFINITY;
        const ucon::sim_object_t* hit = nullptr;
        for (const auto& o : m.objects) {
          const double gap = std::hypot(o.x - m.robot_x, o.y - m.robot_y) - o.radius - m.robot_radius;
          if (gap < best) {
            best = gap;
            hit = &o;
          }
        }
        char buf[256];
        if (hit && best < 0.05) {
          // The track nearest to the mover, if any: was it seen, and how well?
          const ucon::tracked_object_t* tr = nullptr;
          double td = INFINITY;
          for (const auto& t : last_objects_.objects) {
            const double d = std::hypot(t.x - hit->x, t.y - hit->y);
            if (d < td) td = d, tr = &t;
          }
          char trk[128];
          if (tr && td < 1.0)
            std::snprintf(trk, sizeof(trk), "tracked %.2f m off, v err %.2f m/s, state %d", td,
                          std::hypot(tr->vx - hit->vx, tr->vy - hit->vy), int(tr->state));
          else
            std::snprintf(trk, sizeof(trk), "NOT tracked (nearest track %.1f m)", td);
          std::snprintf(buf, sizeof(buf), "mover %lld (%.2f m/s, r %.2f) %s; %s", static_cast<long long>(hit->id),
                        std::hypot(hit->vx, hit->vy), hit->radius, trk, last_plan_.c_str());
          history_ = moverHistory(hit->id);
          hit_mover_ = true;
        } else {
          std::snprintf(buf, sizeof(buf), "static; %s", last_plan_.c_str());
        }
        collision_with_ = buf;
        robot_speed_at_hit_ = std::hypot(m.robot_vx, m.robot_vy);
      }
      collided_ = collided_ || m.collision || m.num_collisions > 0;
    } else {
      return rp::FeedResult::kIgnored;
    }
    return rp::FeedResult::kHandled;
  }

  bool reachedAll() const { return reached_all_; }
  bool collided() const { return collided_; }
  const std::string& collisionWith() const { return collision_with_; }
  bool hitMover() const { return hit_mover_; }
  double robotSpeedAtHit() const { return robot_speed_at_hit_; }
  bool timedOut() const { return node_.done() && !reached_all_; }
  ucon::mission::MissionSummary summary() const { return node_.summary(); }

 private:
  ucon::mission::MissionNode node_;
  bool reached_all_ = false, collided_ = false, hit_mover_ = false;

 public:
  int64_t recall_total_ = 0, recall_hit_ = 0;
  double verr_sum_ = 0.0;
  int64_t verr_n_ = 0;
  double verr2_sum_ = 0.0, vvar_sum_ = 0.0;

 private:
  std::string collision_with_;
  ucon::tracked_objects_t last_objects_;
  std::string last_plan_;
  struct Snapshot {
    ucon::sim_ground_truth_t gt;
    ucon::tracked_objects_t tracks;
    std::string plan;
    std::shared_ptr<const std::vector<uint8_t>> statics;  ///< PERCEPTION_STATIC as published
  };
  std::shared_ptr<const std::vector<uint8_t>> last_static_;
  std::deque<Snapshot> recent_;
  std::string history_;

  // One line per 0.25 s before the hit: the mover and robot as they were, the nearest track.
  std::string moverHistory(int64_t id) const {
    std::string out;
    for (std::size_t k = 0; k < recent_.size(); k += 12) {
      const Snapshot& s = recent_[k];
      const ucon::sim_object_t* o = nullptr;
      for (const auto& c : s.gt.objects)
        if (c.id == id) o = &c;
      if (!o) continue;
      const ucon::tracked_object_t* tr = nullptr;
      double td = INFINITY;
      for (const auto& t : s.tracks.objects) {
        const double d = std::hypot(t.x - o->x, t.y - o->y);
        if (d < td) td = d, tr = &t;
      }
      int on_body = 0;  // static points published on the mover's body (a ghost the map keeps)
      ucon::static_points_t statics;
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

 public:
  const std::string& history() const { return history_; }

 private:
  double robot_speed_at_hit_ = NAN;
  int64_t goals_sent_ = 0;
};

/// Everything a run needs that is read once from files.
struct Setup {
  ucon::simulator::SimulatorParams sim;
  ucon::lidar_driver::DriverParams driver;
  ucon::mission::MissionParams mission;
  std::map<std::string, std::string> node_yaml;  // node name -> YAML text
  std::string config_dir, scenario_dir;
  std::string pose = "ground_truth";  ///< --pose: ground_truth | odometry (odometry_in_loop.hpp)
};

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
  std::string plan_tally;  ///< " fallbacks k=n ...": the planner's counters of what it did when a plan failed its check
  double robot_speed_at_hit = NAN;
  double dist_start_goal = 0.0, dist_left = 0.0;
  std::map<std::string, int64_t> messages;
  int64_t wheel_cmds_applied = 0;
  int64_t leaked_static = 0, static_points = 0;
  double velocity_error = NAN;  ///< mean |v_track - v_mover| [m/s] of tracked movers within 5 m of the robot
  double velocity_error_over_std = NAN;  ///< rms of that error / rms of the velocity std the tracks state
  double recall = NAN;  ///< share of visible movers within 10 m with a track within 0.7 m
  StageTimes stages[kNumStages];
  bool pipelineBroken(std::string* why) const {
    auto count = [&](const char* ch) {
      auto it = messages.find(ch);
      return it == messages.end() ? int64_t{0} : it->second;
    };
    if (!ok) return *why = error, true;
    if (count(ucon::channels::kLidarPoints) == 0) return *why = "no LIDAR_POINTS frames", true;
    if (count(ucon::channels::kPerceptionObjects) == 0) return *why = "no PERCEPTION_OBJECTS", true;
    if (count(ucon::channels::kPlannerTrajectory) == 0) return *why = "no PLANNER_TRAJECTORY", true;
    if (wheel_cmds_applied == 0) return *why = "no wheel command reached the plant", true;
    if (dist_start_goal - dist_left < 1.0) return *why = "the robot did not get 1 m closer to its goal", true;
    return false;
  }
};

struct Oracle {
  bool objects = false, static_map = false, velocity = false;
};

/// How the nodes share the machine: pipelined (perception and planner on threads of their
/// own, as their processes run on the robot, with fixed delivery latencies) or serial (one
/// thread, zero-latency bus).
struct Pipeline {
  bool serial = false;
  int64_t perception_delay_us = 20000;  ///< one LiDAR frame period: a frame's objects are out before the next frame
  int64_t planner_delay_us = 30000;     ///< planner.yaml latency_s: a plan is delivered when it starts
};

RunResult runOne(const Setup& setup, int n_dynamic, uint64_t seed, double timeout_s, Oracle oracle,
                 const Pipeline& pipeline) {
  RunResult res;
  res.n_dynamic = n_dynamic;
  res.seed = seed;
  const std::string spec = "bench:" + std::to_string(n_dynamic) + ":" + std::to_string(seed);
  std::string err;
  auto sc = ucon::simulator::loadScenario(spec, setup.scenario_dir, -1, ucon::runtime::readTextFile, &err);
  if (!sc) {
    res.error = spec + ": " + err;
    return res;
  }
  if (sc->robot.goals.empty()) {
    res.error = spec + ": the scenario has no goal";
    return res;
  }

  std::vector<std::unique_ptr<rp::NodeAdapter>> owned;
  std::vector<std::unique_ptr<rp::NodeAdapter>> timed;
  const struct {
    const char* node;
    int stage;
    const char* unit;
    bool on_input;
  } kNodes[] = {{"perception", 1, ucon::channels::kLidarPoints, true},
                {"planner", 2, ucon::channels::kPlannerTrajectory, false},
                {"base_controller", 3, ucon::channels::kBaseWheelCmd, false}};
  OracleObjectsAdapter* perception_wrap = nullptr;
  std::vector<rp::NodeAdapter*> stage_nodes;  // what the loop feeds, per stage
  for (const auto& n : kNodes) {
    auto a = rp::makeAdapter(n.node, setup.node_yaml.at(n.node), setup.config_dir + "/" + n.node + ".yaml", &err);
    if (!a) {
      res.error = err;
      return res;
    }
    timed.push_back(std::make_unique<TimedAdapter>(a.get(), &res.stages[n.stage], n.unit, n.on_input));
    owned.push_back(std::move(a));
    rp::NodeAdapter* node = timed.back().get();
    if (n.stage == 1) {
      // Outside the timing: the probe's own work is not perception's latency.
      auto w = std::make_unique<OracleObjectsAdapter>(node, 12.0, oracle.objects, oracle.static_map,
                                                      oracle.velocity);
      perception_wrap = w.get();
      node = w.get();
      owned.push_back(std::move(w));
    }
    stage_nodes.push_back(node);
  }
  MissionAdapter mission(setup.mission, sc->robot.goals, timeout_s);

  // Mission first: a pose that reaches a goal updates it before the planner sees the pose.
  std::vector<rp::NodeAdapter*> loop{&mission};
  for (auto* n : stage_nodes) loop.push_back(n);

  rp::RecorderConfig cfg;
  cfg.sim = setup.sim;
  cfg.driver = setup.driver;
  cfg.scenario = *sc;
  std::unique_ptr<rp::NodeAdapter> odometry;
  if (setup.pose == "odometry") {
    if (!(odometry = ucon::bench::odometryInLoop(setup.config_dir, *sc, &cfg.sim, &res.error))) return res;
    loop.push_back(odometry.get());
  }
  cfg.duration_s = timeout_s + 0.1;  // the mission ends the run at timeout_s of pose time
  cfg.send_goal = false;             // the mission sends the goals
  cfg.scripted_plan = false;         // the planner plans
  StageTimes& drv = res.stages[0];
  Clock::time_point drv_t0;
  double frame_ms = 0.0;
  cfg.before_driver = [&] { drv_t0 = Clock::now(); };
  cfg.after_driver = [&](std::size_t frames) {
    const double ms = msSince(drv_t0);
    drv.total_ms += ms;
    frame_ms += ms;
    if (frames > 0) {  // parse + assembly time of the datagrams of one frame
      drv.samples_ms.push_back(frame_ms);
      frame_ms = 0.0;
    }
  };
  cfg.stop = [&] { return mission.reachedAll() || mission.collided() || mission.timedOut(); };
  Clock::time_point wait_t0;
  if (!pipeline.serial) {
    cfg.async_delay_us[1] = pipeline.perception_delay_us;  // loop = mission, perception, planner, controller
    cfg.async_delay_us[2] = pipeline.planner_delay_us;
    cfg.on_wait = [&](bool waiting) {
      if (waiting)
        wait_t0 = Clock::now();
      else
        res.wait_s += msSince(wait_t0) * 1e-3;
    };
  }

  const auto t0 = Clock::now();
  const double cpu0 = ucon::threadCpuSeconds();
  const rp::RecordSummary s =
      rp::recordSimulatedRun(cfg, loop, [](const std::string&, int64_t, const std::vector<uint8_t>&) {});
  res.wall_s = msSince(t0) * 1e-3;
  res.recall = mission.recall_total_ ? double(mission.recall_hit_) / double(mission.recall_total_) : NAN;
  res.velocity_error = mission.verr_n_ ? mission.verr_sum_ / double(mission.verr_n_) : NAN;
  res.velocity_error_over_std = mission.vvar_sum_ > 0.0 ? std::sqrt(mission.verr2_sum_ / mission.vvar_sum_) : NAN;
  if (perception_wrap) {
    res.leaked_static = perception_wrap->leaked_points_;
    res.static_points = perception_wrap->static_points_;
  }
  res.cpu_s = ucon::threadCpuSeconds() - cpu0 + s.worker_cpu_s;
  for (const rp::NodeAdapter* n : stage_nodes) res.cpu_s += n->helperCpuSeconds();  // the map's helper thread
  res.collision_with = mission.collisionWith() + mission.history();
  res.hit_mover = mission.hitMover();
  for (const auto& [k, n] : stage_nodes[1]->counters()) {
    static const std::map<std::string, std::string> kShown{
        {"result_kept_previous", "kept"},       {"result_stop_no_feasible", "stop"},
        {"least_bad_plans", "least_bad"},       {"evasive_plans", "evasive"},
        {"evasive_manoeuvres", "manoeuvre"},    {"evasion_kept", "evasion_kept"},
        {"rejected_limit_violation", "rejected_limits"}, {"rejected_dynamic_collision", "rejected_mover"},
        {"rejected_static_collision", "rejected_static"}};
    const auto it = kShown.find(k);
    if (it != kShown.end() && n > 0)
      res.plan_tally += (res.plan_tally.empty() ? " fallbacks " : " ") + it->second + "=" + std::to_string(n);
  }
  res.robot_speed_at_hit = mission.robotSpeedAtHit();
  res.ok = true;
  res.sim_s = s.sim_time_s;
  res.messages = s.messages;
  res.wheel_cmds_applied = s.wheel_cmds_applied;
  res.min_clearance = s.min_clearance;
  const Eigen::Vector2d goal = sc->robot.goals.back();
  res.dist_start_goal = (sc->robot.start - goal).norm();
  res.dist_left = (Eigen::Vector2d(s.final_x, s.final_y) - goal).norm();
  const auto ms = mission.summary();
  res.collision = s.collision_episodes > 0 || mission.collided();
  res.success = mission.reachedAll() && !res.collision;
  res.timeout = !mission.reachedAll() && !res.collision;
  if (mission.reachedAll()) res.time_to_goal_s = ms.time_to_goals_s;
  return res;
}

template <class P>
bool loadParamsFile(const std::string& path, P* out, std::string* text, std::string* err) {
  auto t = ucon::runtime::readTextFile(path, err);
  if (!t) return false;
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<P>(*t, path, &errors);
  if (!p) {
    *err = path + ":";
    for (const auto& e : errors) *err += " " + e.toString();
    return false;
  }
  *out = *p;
  if (text) *text = *t;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "UCON full-stack navigation benchmark: simulated Mid-360 packets -> driver -> perception -> planner -> "
      "base controller -> Mecanum plant, in-process, on bench:<N_d>:<seed>."};
  std::string json_path;
  int seeds = 10;
  uint64_t seed_base = 1;
  std::string densities = "50,80,110";
  int jobs = 1;
  bool quick = false, verbose = false;
  Oracle oracle;
  Pipeline pipeline;
  double timeout_s = 120.0;
  Setup setup;
  setup.config_dir = std::string(UCON_SOURCE_DIR) + "/deploy/config";
  setup.scenario_dir = std::string(UCON_SOURCE_DIR) + "/deploy/scenarios";
  app.add_option("--json", json_path, "write results as JSON to this file");
  app.add_option("--seeds", seeds, "worlds per density (seeds B .. B+N-1)")->check(CLI::PositiveNumber);
  app.add_option("--seed-base", seed_base, "first seed");
  app.add_option("--densities", densities, "comma list of moving-obstacle counts N_d");
  app.add_option("--jobs", jobs, "parallel runs (threads)")->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick,
               "pipeline check for ctest: 1 seed at N_d = 50, 20 s timeout; exit 1 only if the pipeline breaks");
  app.add_option("--timeout", timeout_s, "simulated seconds allowed per run [s]")->check(CLI::PositiveNumber);
  app.add_option("--config-dir", setup.config_dir,
                 "folder of simulator.yaml, lidar_driver.yaml, perception.yaml, planner.yaml, "
                 "base_controller.yaml, mission.yaml");
  app.add_option("--scenario-dir", setup.scenario_dir, "folder of the builtin scenarios");
  app.add_flag("--verbose", verbose, "one line per run as it ends");
  app.add_flag("--oracle-objects", oracle.objects,
               "diagnosis: the planner gets the ground-truth movers within 12 m instead of perception's tracks");
  app.add_flag("--oracle-velocity", oracle.velocity,
               "diagnosis: perception's tracks, each with the velocity of the ground-truth mover within 0.8 m");
  app.add_flag("--oracle-static", oracle.static_map,
               "diagnosis: points within 0.25 m of a mover are removed from PERCEPTION_STATIC");
  app.add_option("--pose", setup.pose, "robot pose: ground_truth (the simulator's) | odometry (LiDAR-inertial)")
      ->check(CLI::IsMember({"ground_truth", "odometry"}));
  app.add_flag("--serial", pipeline.serial,
               "run every node on the loop's thread with a zero-latency bus (default: perception and planner "
               "on threads of their own, outputs delivered after a fixed latency)");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    if (app.count("--seeds") == 0) seeds = 1;
    if (app.count("--densities") == 0) densities = "50";
    if (app.count("--timeout") == 0) timeout_s = 20.0;
    verbose = true;
  }

  std::string err;
  if (!loadParamsFile(setup.config_dir + "/simulator.yaml", &setup.sim, nullptr, &err) ||
      !loadParamsFile(setup.config_dir + "/lidar_driver.yaml", &setup.driver, nullptr, &err) ||
      !loadParamsFile(setup.config_dir + "/mission.yaml", &setup.mission, nullptr, &err)) {
    std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
    return 2;
  }
  if (const std::string bad = setup.sim.validate(); !bad.empty()) {
    std::fprintf(stderr, "ucon-bench-nav: simulator.yaml: %s\n", bad.c_str());
    return 2;
  }
  for (const char* n : {"perception", "planner", "base_controller"}) {
    const std::string path = setup.config_dir + "/" + n + ".yaml";
    auto t = ucon::runtime::readTextFile(path, &err);
    if (!t) {
      std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
      return 2;
    }
    // Fail early on a bad config or a node missing from this build.
    if (!rp::makeAdapter(n, *t, path, &err)) {
      std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
      return 2;
    }
    setup.node_yaml[n] = *t;
  }
  {
    // Pipeline latencies: a LiDAR frame period for perception, the planner's own latency_s.
    ucon::planner::PlannerParams pp;
    if (!loadParamsFile(setup.config_dir + "/planner.yaml", &pp, nullptr, &err)) {
      std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
      return 2;
    }
    pipeline.perception_delay_us = std::llround(1e6 / setup.sim.frame_rate_hz);
    pipeline.planner_delay_us = std::max<int64_t>(std::llround(pp.latency_s * 1e6), 1000);
  }
  std::vector<int> density_list;
  for (const auto& d : split(densities)) {
    const int n = std::atoi(d.c_str());
    if (n < 0) {
      std::fprintf(stderr, "ucon-bench-nav: bad density '%s'\n", d.c_str());
      return 2;
    }
    density_list.push_back(n);
  }

  struct Task {
    int n_dynamic;
    uint64_t seed;
  };
  std::vector<Task> tasks;
  for (int s = 0; s < seeds; ++s)
    for (int d : density_list) tasks.push_back({d, seed_base + uint64_t(s)});
  std::vector<RunResult> results(tasks.size());
  std::atomic<std::size_t> next{0};
  std::mutex print_mutex;
  const auto bench_t0 = Clock::now();
  auto worker = [&] {
    for (std::size_t i = next++; i < tasks.size(); i = next++) {
      results[i] = runOne(setup, tasks[i].n_dynamic, tasks[i].seed, timeout_s, oracle, pipeline);
      const auto& r = results[i];
      if (verbose || !r.ok) {
        std::lock_guard<std::mutex> lock(print_mutex);
        if (!r.ok) {
          std::printf("N_d=%3d seed=%4llu ERROR %s\n", r.n_dynamic, (unsigned long long)r.seed, r.error.c_str());
        } else {
          std::printf("N_d=%3d seed=%4llu %-9s t_goal=%6.1fs sim=%6.1fs wall=%6.1fs rtf=%5.2f left=%5.1fm "
                      "clear=%5.2fm frames=%lld plans=%lld leak=%.1f/s recall=%.2f verr=%.2f | med ms drv %.3f per %.2f pln %.2f ctl %.3f | cpu rtf %.2f%s%s%s\n",
                      r.n_dynamic, (unsigned long long)r.seed,
                      r.success ? "success" : (r.collision ? "COLLISION" : "timeout"), r.time_to_goal_s, r.sim_s,
                      r.wall_s, r.wall_s > 0 ? r.sim_s / r.wall_s : NAN, r.dist_left, r.min_clearance,
                      (long long)(r.messages.count(ucon::channels::kLidarPoints) ? r.messages.at(ucon::channels::kLidarPoints) : 0),
                      (long long)(r.messages.count(ucon::channels::kPlannerTrajectory) ? r.messages.at(ucon::channels::kPlannerTrajectory) : 0),
                      r.sim_s > 0 ? r.leaked_static / r.sim_s : NAN, r.recall, r.velocity_error, percentile(r.stages[0].samples_ms, 0.5), percentile(r.stages[1].samples_ms, 0.5),
                      percentile(r.stages[2].samples_ms, 0.5), percentile(r.stages[3].samples_ms, 0.5),
                      r.cpu_s > 0 ? r.sim_s / r.cpu_s : NAN, r.plan_tally.c_str(), r.collision ? " | hit " : "",
                      r.collision ? (r.collision_with + " at robot speed " + num(r.robot_speed_at_hit) + " m/s").c_str() : "");
        }
        std::fflush(stdout);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, jobs); ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  const double bench_wall_s = msSince(bench_t0) * 1e-3;

  struct Row {
    int n_dynamic = 0;
    int runs = 0, successes = 0, collisions = 0, timeouts = 0;
    std::vector<double> ttg;
    double sim_s = 0.0, wall_s = 0.0, cpu_s = 0.0, wait_s = 0.0;
    int hit_mover = 0, hit_static = 0;
    std::vector<double> recall, verr, vcons;  // per run
    std::vector<double> samples[kNumStages];
    double stage_total_ms[kNumStages] = {0, 0, 0, 0};
    std::map<std::string, double> by_input_ms[kNumStages];
  };
  std::vector<Row> rows;
  int rc = 0;
  for (int d : density_list) {
    Row row;
    row.n_dynamic = d;
    for (const auto& r : results) {
      if (r.n_dynamic != d) continue;
      std::string why;
      if (r.pipelineBroken(&why)) {
        std::fprintf(stderr, "ucon-bench-nav: pipeline broken at bench:%d:%llu: %s\n", d,
                     (unsigned long long)r.seed, why.c_str());
        rc = 1;
      }
      if (!r.ok) continue;
      ++row.runs;
      row.successes += r.success;
      row.collisions += r.collision;
      row.timeouts += r.timeout;
      if (r.success) row.ttg.push_back(r.time_to_goal_s);
      row.sim_s += r.sim_s;
      row.wall_s += r.wall_s;
      row.cpu_s += r.cpu_s;
      row.wait_s += r.wait_s;
      if (r.collision) (r.hit_mover ? row.hit_mover : row.hit_static) += 1;
      if (std::isfinite(r.recall)) row.recall.push_back(r.recall);
      if (std::isfinite(r.velocity_error)) row.verr.push_back(r.velocity_error);
      if (std::isfinite(r.velocity_error_over_std)) row.vcons.push_back(r.velocity_error_over_std);
      for (int k = 0; k < kNumStages; ++k) {
        row.samples[k].insert(row.samples[k].end(), r.stages[k].samples_ms.begin(), r.stages[k].samples_ms.end());
        row.stage_total_ms[k] += r.stages[k].total_ms;
        for (const auto& [ch, ms] : r.stages[k].by_input_ms) row.by_input_ms[k][ch] += ms;
      }
    }
    rows.push_back(std::move(row));
  }
  auto mean = [](const std::vector<double>& v) {
    if (v.empty()) return double(NAN);
    double s = 0.0;
    for (double x : v) s += x;
    return s / double(v.size());
  };

  std::printf("\nFull-stack navigation on bench:<N_d>:<seed> (%d seeds from %llu, timeout %.0f s, %u hardware "
              "threads, %d jobs, %.1f s wall)\n",
              seeds, (unsigned long long)seed_base, timeout_s, std::thread::hardware_concurrency(), jobs,
              bench_wall_s);
  if (pipeline.serial)
    std::printf("serial: every node on the loop's thread, zero-latency bus\n");
  else
    std::printf("pipelined: perception and planner on threads of their own (per run), their outputs delivered "
                "%.0f ms and %.0f ms after their inputs (--serial: one thread)\n",
                1e-3 * double(pipeline.perception_delay_us), 1e-3 * double(pipeline.planner_delay_us));
  std::printf("%5s %5s | %8s %5s %6s | %9s %9s | %6s %6s | %s\n", "N_d", "runs", "succ[%]", "coll", "tmout",
              "t_goal[s]", "t_goal_md", "RT x", "RT cpu", "median latency [ms]: driver/frame  perception/frame  "
              "planner/plan  controller/tick");
  for (const auto& r : rows) {
    std::printf("%5d %5d | %8.1f %5d %6d | %9.1f %9.1f | %6.2f %6.2f | %8.3f %8.2f %8.2f %8.3f\n", r.n_dynamic, r.runs,
                r.runs ? 100.0 * r.successes / r.runs : NAN, r.collisions, r.timeouts, mean(r.ttg),
                percentile(r.ttg, 0.5), r.wall_s > 0 ? r.sim_s / r.wall_s : NAN,
                r.cpu_s > 0 ? r.sim_s / r.cpu_s : NAN, percentile(r.samples[0], 0.5),
                percentile(r.samples[1], 0.5), percentile(r.samples[2], 0.5), percentile(r.samples[3], 0.5));
  }
  std::printf("(RT x = simulated seconds / wall seconds of the whole loop, simulator included, per run;\n"
              " RT cpu = simulated seconds / CPU seconds of the run's threads together, i.e. of one core doing it all;\n"
              " coll = runs that ended in a collision; t_goal = mean / median over successful runs)\n");
  std::printf("collisions with movers / static obstacles:");
  for (const auto& r : rows) std::printf("  N_d=%d: %d / %d", r.n_dynamic, r.hit_mover, r.hit_static);
  std::printf("\n");
  std::printf("tracking, median over runs: recall (visible movers within 10 m with a track within 0.7 m) / "
              "velocity error of those within 5 m [m/s] / that error over the std the tracks state (1: consistent):");
  for (const auto& r : rows)
    std::printf("  N_d=%d: %.3f / %.3f / %.2f", r.n_dynamic, percentile(r.recall, 0.5), percentile(r.verr, 0.5),
                percentile(r.vcons, 0.5));
  std::printf("\n");
  if (pipeline.serial)
    std::printf("\nWall time per simulated second [ms] (share of the loop): driver, perception, planner, "
                "controller, simulator+bus\n");
  else
    std::printf("\nWall time per simulated second [ms] (share of the run's wall time): nodes (perception and "
                "planner on their own threads, overlapping the loop), then the loop thread's waits for them and "
                "the rest of the loop thread (simulator+bus)\n");
  for (const auto& r : rows) {
    if (r.sim_s <= 0) continue;
    double on_loop = 0.0;
    std::printf("%5d |", r.n_dynamic);
    for (int k = 0; k < kNumStages; ++k) {
      if (pipeline.serial || k == 0 || k == 3) on_loop += r.stage_total_ms[k];
      std::printf(" %s %7.1f (%4.1f%%)", kStages[k], r.stage_total_ms[k] / r.sim_s,
                  100.0 * r.stage_total_ms[k] / (1e3 * r.wall_s));
    }
    if (!pipeline.serial) {
      on_loop += 1e3 * r.wait_s;
      std::printf(" | waiting %7.1f (%4.1f%%)", 1e3 * r.wait_s / r.sim_s, 100.0 * r.wait_s / r.wall_s);
    }
    const double rest = 1e3 * r.wall_s - on_loop;
    std::printf(" | rest %7.1f (%4.1f%%)\n", rest / r.sim_s, 100.0 * rest / (1e3 * r.wall_s));
  }
  std::printf("Node wall time per simulated second by input channel [ms]:\n");
  for (const auto& r : rows) {
    if (r.sim_s <= 0) continue;
    std::printf("%5d |", r.n_dynamic);
    for (int k = 1; k < kNumStages; ++k) {
      for (const auto& [ch, ms] : r.by_input_ms[k]) std::printf(" %s<-%s %.1f", kStages[k], ch.c_str(), ms / r.sim_s);
    }
    std::printf("\n");
  }
  std::printf("p95 latency [ms]:\n");
  for (const auto& r : rows) {
    std::printf("%5d |", r.n_dynamic);
    for (int k = 0; k < kNumStages; ++k) std::printf(" %s %8.3f", kStages[k], percentile(r.samples[k], 0.95));
    std::printf("\n");
  }

  if (!json_path.empty()) {
    std::ofstream js(json_path);
    js << "{\"results\": [";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      js << (i ? ",\n  " : "\n  ") << "{\"n_dynamic\": " << r.n_dynamic << ", \"runs\": " << r.runs
         << ", \"success_rate\": " << num(r.runs ? double(r.successes) / r.runs : NAN)
         << ", \"collisions\": " << r.collisions << ", \"time_to_goal_s\": " << num(mean(r.ttg))
         << ", \"realtime_factor\": " << num(r.wall_s > 0 ? r.sim_s / r.wall_s : NAN)
         << ", \"realtime_factor_cpu\": " << num(r.cpu_s > 0 ? r.sim_s / r.cpu_s : NAN)
         << ", \"pipelined\": " << (pipeline.serial ? "false" : "true")
         << ", \"tracking_recall\": " << num(percentile(r.recall, 0.5))
         << ", \"velocity_error_mps\": " << num(percentile(r.verr, 0.5))
         << ", \"velocity_error_over_std\": " << num(percentile(r.vcons, 0.5)) << ", \"latency_ms\": {";
      for (int k = 0; k < kNumStages; ++k) {
        js << (k ? ", " : "") << "\"" << kStages[k] << "\": " << num(percentile(r.samples[k], 0.5));
      }
      js << "}}";
    }
    js << "\n]}\n";
    js.close();
    if (!js) {
      std::fprintf(stderr, "ucon-bench-nav: cannot write %s\n", json_path.c_str());
      return 1;
    }
    std::printf("wrote %s\n", json_path.c_str());
  }
  return rc;
}
