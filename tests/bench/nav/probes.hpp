#pragma once
/// @file probes.hpp
/// Wrappers around the nodes of a bench nav run that measure or diagnose without changing what
/// the nodes compute: the stage timer, and the perception probe (static points leaked onto
/// movers; the --oracle-* diagnoses).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ucon/replay/node_adapter.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"

namespace ucon::bench::nav {

namespace rp = ucon::replay;
using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

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
                      std::vector<rp::OutputMessage>* out) override;
  /// The node timed from now on (a restarted node: --faults kill=...,restart=...).
  void setInner(rp::NodeAdapter* inner) { inner_ = inner; }

 private:
  rp::NodeAdapter* inner_;
  StageTimes* times_;
  std::string unit_;
  bool on_input_;
};

/// A mover with less of its silhouette in the sensor's view than this is hidden.
constexpr double kHiddenVisibility = 0.3;

/// Which --oracle-* diagnoses a run uses.
struct Oracle {
  bool objects = false, static_map = false, velocity = false;
  bool line_of_sight = false;  ///< with objects: only the movers the sensor sees, the hidden ones coasted
  double delay_s = 0.0;        ///< with line_of_sight: a mover is published once in view this long [s]
};

/// PERCEPTION_OBJECTS made from the simulator's ground truth: every mover within `range` [m] of
/// the robot as a confirmed track with its exact position and velocity and a small fixed
/// covariance (--oracle-objects). This and LineOfSightOracle are where this benchmark builds
/// track messages (one exact estimate for both).
tracked_objects_t oracleObjects(const sim_ground_truth_t& gt, double range, int64_t seq);

/// What a tracker that is perfect on what the sensor sees would publish (--oracle-objects
/// --oracle-line-of-sight): every mover within `range` [m] of the robot that has had at least
/// kHiddenVisibility of its silhouette in view for `delay` [s] (0: at once), with its exact
/// state, as a confirmed track; a mover so published and hidden since, for at most `max_coast`
/// [s], as a coasting track at its last seen position carried on with its last seen velocity,
/// its position std growing by kCoastStdPerS per second hidden (a walker may turn). A mover not
/// yet so long in view is not published (--oracle-delay: how soon perception must hold a mover
/// that comes into view).
class LineOfSightOracle {
 public:
  static constexpr double kCoastStdPerS = 0.5;  // [m/s]
  LineOfSightOracle(double range, double max_coast, double delay)
      : range_(range), max_coast_(max_coast), delay_(delay) {}
  tracked_objects_t objects(const sim_ground_truth_t& gt, int64_t seq);

 private:
  struct Seen {
    int64_t utime = 0;          ///< last time in view
    int64_t in_view_since = 0;  ///< since when in view without a break
    bool published = false;     ///< in view for `delay` since in_view_since (a track exists)
    double x = 0, y = 0, vx = 0, vy = 0, radius = 0, height = 0;
  };
  double range_, max_coast_, delay_;
  std::map<int64_t, Seen> last_seen_;  ///< by mover id
  int64_t prev_utime_ = 0;             ///< the previous ground-truth step
};

/// Diagnosis: wraps (timed) perception. Always counts PERCEPTION_STATIC points that lie on a
/// mover's body (the leak). --oracle-objects drops its PERCEPTION_OBJECTS and publishes
/// oracleObjects() instead; --oracle-velocity keeps perception's tracks but gives each the
/// velocity of the ground-truth mover within 0.8 m of it; --oracle-static removes from
/// PERCEPTION_STATIC every point within 0.25 m of a mover's body. Runs then show what planning
/// and control do with perfect tracking (or perfect velocities) and/or a static map that movers
/// never pollute.
class PerceptionProbe : public rp::NodeAdapter {
 public:
  PerceptionProbe(rp::NodeAdapter* inner, double range, const Oracle& oracle, double max_coast)
      : inner_(inner), range_(range), oracle_(oracle), line_of_sight_(range, max_coast, oracle.delay_s) {}
  std::string name() const override { return inner_->name(); }
  std::vector<std::string> inputChannels() const override;
  std::vector<std::string> outputChannels() const override { return inner_->outputChannels(); }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return inner_->counters(); }
  double helperCpuSeconds() const override { return inner_->helperCpuSeconds(); }
  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override;

  int64_t leakedPoints() const { return leaked_points_; }
  int64_t staticPoints() const { return static_points_; }

 private:
  /// Perception's outputs of one feed, from index `begin` on, as the oracle flags say.
  void probeOutputs(std::vector<rp::OutputMessage>* out, std::size_t begin);
  /// Counts the points of `s` within 0.1 m of the surface of a mover within 15 m of the robot.
  void countLeak(const static_points_t& s);

  rp::NodeAdapter* inner_;
  double range_;
  Oracle oracle_;
  int64_t leaked_points_ = 0, static_points_ = 0;
  sim_ground_truth_t last_gt_;
  int64_t seq_ = 0;
  LineOfSightOracle line_of_sight_;
};

}  // namespace ucon::bench::nav
