#pragma once
/// @file sim_recorder.hpp
/// Records a simulated run in-process and deterministically: the Simulator (world, Mecanum
/// base, Mid-360 packets), the lidar driver node (packets -> LIDAR_POINTS, LIDAR_IMU) and the
/// given nodes, connected as a zero-latency bus without LCM. Every message is handed to the
/// sink (the log) at the moment it is published and, in the same order, to every node that
/// consumes it; a node's outputs are published at once (depth first); BASE_WHEEL_CMD drives
/// the simulated base. So replaying any recorded node over the log (NodeAdapter, same feeding
/// rule) reproduces its recorded outputs exactly, and the same config gives the same bytes on
/// every run. Nothing here reads a clock, a socket or a file.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/world/scenario.hpp"

namespace ucon {
namespace replay {

/// Faults on the bus (ucon-bench-nav --faults): deliveries of messages to the nodes and to the
/// simulated base lost or late, and nodes killed and restarted from an empty state, as a
/// robot's network and process supervisor do to them. A delivery is one message to one
/// consumer; a late one is handed over at the first step at or after its due time, so late
/// messages can overtake each other (UDP does that). Deterministic: every decision is a hash of
/// `seed`, the message's place in the bus order and the consumer, never a clock.
struct BusFaults {
  double drop = 0.0;          ///< probability that one delivery is lost, [0, 1]
  int64_t delay_us = 0;       ///< every affected delivery is late by this [us], >= 0
  int64_t jitter_us = 0;      ///< ... plus a uniform draw from [0, jitter_us] [us], >= 0
  /// Channels whose deliveries are affected (ECMAScript regular expression, whole name);
  /// empty: every channel. SIM_GROUND_TRUTH and LOG_METADATA (the harness's, not the robot's)
  /// never are.
  std::string channels;
  uint64_t seed = 0;
  /// A node killed at `at_us` after the start of the run: nothing is delivered to it and
  /// nothing it had in flight is published; restarted `restart_after_us` later (< 0: never) by
  /// `restart`, as a respawn would.
  struct Kill {
    std::size_t node = 0;  ///< index into the run's nodes
    int64_t at_us = 0;
    int64_t restart_after_us = -1;
  };
  std::vector<Kill> kills;
  /// Makes node i afresh (empty state) and returns the adapter the bus feeds from then on
  /// (owned by the caller; may be the same wrapper around a new node). Required for a restart.
  std::function<NodeAdapter*(std::size_t node)> restart;

  bool any() const { return drop > 0.0 || delay_us > 0 || jitter_us > 0 || !kills.empty(); }
};

/// What to record.
struct RecorderConfig {
  simulator::SimulatorParams sim;
  lidar_driver::DriverParams driver;
  world::Scenario scenario;
  double duration_s = 4.0;       ///< simulated seconds recorded, (0, 3600]
  int64_t step_us = 1000;        ///< simulation step between bus deliveries [us], [100, 10000]
  /// Publish NAV_GOAL (the scenario's first goal) at the start.
  bool send_goal = true;
  /// Publish a scripted PLANNER_TRAJECTORY (10 Hz, one plan: a minimum-jerk straight line
  /// toward the goal at up to scripted_speed) for when no planner is in the loop.
  bool scripted_plan = true;
  double scripted_speed = 1.0;   ///< peak speed of the scripted plan [m/s], (0, 3]
  double scripted_length = 3.0;  ///< longest scripted drive [m], (0, 100]
  /// (key, value) pairs for the LOG_METADATA event written first (e.g. "config/x.yaml", text).
  std::vector<std::pair<std::string, std::string>> metadata;

  // Optional hooks for harnesses that run the same loop to measure it (ucon-bench-nav). They
  // are called synchronously; nothing here reads a clock, the hooks may.
  /// Called just before a datagram is handed to the lidar driver.
  std::function<void()> before_driver;
  /// Called just after, with the number of point frames that datagram completed.
  std::function<void(std::size_t frames_completed)> after_driver;
  /// Checked after every step; true ends the run before duration_s (e.g. goal reached).
  std::function<bool()> stop;

  /// Pipelining (ucon-bench-nav): nodes listed here (index into `nodes` -> delay [us]) run on a
  /// worker thread each, as their processes do on the robot, instead of on the loop's thread.
  /// Their inputs are queued in bus order; an output becomes due `delay` after the bus time of
  /// the input that caused it and is published at the first step at or after that (before the
  /// simulator's messages of that step), waiting for the worker if it is behind. The outputs
  /// and the message order therefore depend only on the inputs, never on thread timing: the
  /// run is as deterministic as the lock-step loop, with a fixed latency per node in place of
  /// the zero-latency bus. A delay must be at least step_us. The log then holds a node's
  /// outputs at their delivery time (their utime stays the node's own): meant for harnesses,
  /// not for recording logs to replay.
  std::map<std::size_t, int64_t> async_delay_us;
  /// Called with true just before the loop waits for a worker that is behind, false after.
  std::function<void(bool waiting)> on_wait;
  /// Faults injected on the bus (none by default). Like pipelining, meant for harnesses.
  BusFaults faults;
};

/// Receives every message in publication order: channel, utime [us] (used as the event
/// timestamp), encoded bytes.
using EventSink = std::function<void(const std::string& channel, int64_t utime, const std::vector<uint8_t>& data)>;

struct RecordSummary {
  std::map<std::string, int64_t> messages;  ///< per channel
  int64_t wheel_cmds_applied = 0;
  double final_x = 0.0, final_y = 0.0;      ///< robot position at the end [m]
  double min_clearance = 0.0;               ///< [m]
  double sim_time_s = 0.0;                  ///< simulated seconds run (< duration_s if stopped)
  int64_t collision_episodes = 0;           ///< simulator's count
  double worker_cpu_s = 0.0;                ///< CPU seconds of the async nodes' worker threads
  /// Faults injected (RecorderConfig::faults): deliveries lost, deliveries late, deliveries
  /// and outputs lost to a killed node, restarts.
  int64_t faults_dropped = 0, faults_delayed = 0, faults_killed_deliveries = 0, faults_killed_outputs = 0,
          faults_restarts = 0;
};

/// Runs the closed loop for config.duration_s. `nodes` are fed in the given order; their
/// inputChannels() are read once at the start.
RecordSummary recordSimulatedRun(const RecorderConfig& config,
                                 const std::vector<NodeAdapter*>& nodes, const EventSink& sink);

}  // namespace replay
}  // namespace ucon
