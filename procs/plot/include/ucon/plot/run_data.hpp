#pragma once
/// @file run_data.hpp
/// What a picture or a playback of a run needs, extracted from the messages of its LCM log:
/// robot path, simulator ground truth, tracked objects with covariance, static points (as an
/// occupancy grid), planned trajectories (sampled) and collisions. Decoding is strict: an
/// undecodable or non-finite message is skipped and counted, never trusted.

#include <Eigen/Core>

#include <climits>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ucon {
namespace plot {

/// One robot pose [m, rad, m/s].
struct PoseSample {
  int64_t utime = 0;  ///< [us]
  double x = 0.0, y = 0.0, yaw = 0.0;
  double vx = 0.0, vy = 0.0;
  double speed() const;
};

/// One tracked object of one PERCEPTION_OBJECTS frame.
struct TrackedState {
  int64_t id = 0;
  int state = 0;                ///< tracked_object_t::STATE_*
  double x = 0.0, y = 0.0;      ///< [m]
  double vx = 0.0, vy = 0.0;    ///< [m/s]
  bool has_cov = false;         ///< false: cov_size was 0 or the x-y block is not PSD/finite
  Eigen::Matrix2d cov_xy = Eigen::Matrix2d::Zero();  ///< x-y block of the position covariance [m^2]
  double size_x = 0.0, size_y = 0.0, yaw = 0.0;      ///< box [m, m, rad]
};

struct ObjectsFrame {
  int64_t utime = 0;
  std::vector<TrackedState> objects;
};

/// One moving obstacle of the simulator's ground truth.
struct GroundTruthObject {
  int64_t id = 0;
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0, radius = 0.0;  ///< [m, m/s]
};

struct GroundTruthFrame {
  int64_t utime = 0;
  PoseSample robot;
  double robot_radius = 0.0;  ///< [m]
  bool collision = false;
  int num_collisions = 0;
  double min_clearance = 0.0;  ///< [m]
  std::vector<GroundTruthObject> objects;
};

/// A planned trajectory sampled in time, for drawing.
struct TrajectorySnapshot {
  int64_t utime = 0;           ///< when it was planned [us]
  int64_t plan_id = 0;
  int status = 0;              ///< trajectory_t::STATUS_*
  std::vector<Eigen::Vector2d> points;  ///< x-y every TrajectoryExtraction::sample_step_s [m]
};

/// A collision episode (ground truth collision flag rising).
struct CollisionEvent {
  int64_t utime = 0;
  double x = 0.0, y = 0.0;  ///< robot centre [m]
};

/// Static points accumulated on a 2-D grid.
struct StaticCell {
  int64_t hits = 0;          ///< points that fell into the cell over the run
  int64_t first_utime = 0;   ///< when the cell was first hit [us]
};

struct StaticGrid {
  double resolution = 0.1;   ///< cell size [m]
  std::map<std::pair<int32_t, int32_t>, StaticCell> cells;  ///< (ix, iy) -> cell; ordered = deterministic
  Eigen::Vector2d centre(const std::pair<int32_t, int32_t>& key) const;
};

/// How the log is turned into RunData.
struct ExtractionParams {
  double static_resolution = 0.1;      ///< static grid cell [m], 0.01..10
  double static_min_z = 0.05;          ///< static points below this height are floor, ignored [m]
  double static_max_z = 2.5;           ///< and above this, ceiling [m]
  double trajectory_step_s = 0.1;      ///< sampling of planned trajectories [s], > 0
  double max_coordinate = 1e5;         ///< |x|,|y| above this is treated as corrupt [m]
  double clock_tolerance_s = 1.0;      ///< channels whose clocks differ by more are re-based [s]
};

/// Everything extracted from one run.
struct RunData {
  std::string scenario;                         ///< from SIM_GROUND_TRUTH, empty if none
  std::vector<PoseSample> poses;                ///< ROBOT_POSE (valid ones), time order of the log
  std::vector<GroundTruthFrame> ground_truth;   ///< SIM_GROUND_TRUTH
  std::vector<ObjectsFrame> objects;            ///< PERCEPTION_OBJECTS (valid frames)
  std::vector<TrajectorySnapshot> trajectories; ///< PLANNER_TRAJECTORY
  std::vector<CollisionEvent> collisions;       ///< from ground truth
  StaticGrid static_grid;                       ///< PERCEPTION_STATIC
  int64_t static_messages = 0;
  std::map<std::string, int64_t> used;          ///< channel -> messages used
  std::map<std::string, int64_t> skipped;       ///< "CHANNEL: reason" -> messages skipped
  std::vector<std::string> notes;               ///< what the reader did about odd input (clock re-basing)
  int64_t events = 0;                           ///< log events read (all channels)

  /// True when no message of any channel this tool draws was used.
  bool empty() const;
  /// Robot path: ROBOT_POSE when there is one, else the ground truth's robot.
  std::vector<PoseSample> robotPath() const;
  /// First and last utime over every extracted message; {0, 0} when empty.
  std::pair<int64_t, int64_t> timeRange() const;
  /// Robot radius from the ground truth, else `fallback` [m].
  double robotRadius(double fallback = 0.3) const;
};

/// Channels this tool reads, for messages ("ROBOT_POSE, SIM_GROUND_TRUTH, ...").
std::string channelsRead();

/// Builds RunData message by message (no I/O: the caller reads the log).
class RunDataBuilder {
 public:
  explicit RunDataBuilder(const ExtractionParams& params = {});
  static constexpr int64_t kNoTimestamp = INT64_MIN;

  /// Decodes and adds one message. Channels that are not drawn are ignored; bad messages are
  /// counted in RunData::skipped. `log_timestamp` is the log's receive time of the event [us]
  /// (one clock for every channel), used by take() to detect channels on different clocks.
  /// Never throws.
  void add(const std::string& channel, const uint8_t* data, std::size_t size,
           int64_t log_timestamp = kNoTimestamp);
  /// Counts one log event that was read (whatever its channel).
  void countEvent() { ++data_.events; }
  const RunData& data() const { return data_; }
  /// The run. When channels' utimes are on different clocks (e.g. perception stamped with
  /// the sensor's or the host's clock, the pose with simulation time: their median offsets to
  /// the log's receive time differ by more than `clock_tolerance_s`), each channel's utimes are
  /// moved onto the clock of the first of ROBOT_POSE, SIM_GROUND_TRUTH, PERCEPTION_OBJECTS,
  /// PLANNER_TRAJECTORY, PERCEPTION_STATIC, using the receive times, and a note says so.
  RunData take();

 private:
  void skip(const std::string& channel, const std::string& reason);
  void addPose(const uint8_t* data, std::size_t size);
  void addGroundTruth(const uint8_t* data, std::size_t size);
  void addObjects(const uint8_t* data, std::size_t size);
  void addStatic(const uint8_t* data, std::size_t size);
  void addTrajectory(const uint8_t* data, std::size_t size);

  ExtractionParams params_;
  RunData data_;
  void noteClock(const char* channel, int64_t utime);
  void alignClocks();

  bool last_collision_ = false;
  int64_t current_timestamp_ = kNoTimestamp;
  std::map<std::string, std::vector<int64_t>> clock_offsets_;  // channel -> utime - receive time (sampled)
};

enum class LoadStatus { kOk, kOpenFailed, kCorrupt, kNoChannels };
const char* toString(LoadStatus s);

/// Reads an LCM log file into RunData with the strict log reader. kCorrupt: the log is damaged
/// (error names the byte offset); `out` then holds what came before the damage. kNoChannels:
/// the log has none of the channels this tool reads (error lists them).
LoadStatus loadRunLog(const std::string& path, const ExtractionParams& params, RunData* out,
                      std::string* error);

}  // namespace plot
}  // namespace ucon
