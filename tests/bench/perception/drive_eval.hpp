#pragma once
/// @file drive_eval.hpp
/// Perception measured from a moving robot (`ucon-bench-perception --drive`), in two steps:
///
///  1. record: one closed-loop run per scene and seed, in-process and in lock step
///     (ucon::replay::recordSimulatedRun): the simulator's Mid-360 packets through the lidar
///     driver, a patrol that sends the route's goals on NAV_GOAL, and the nodes that move the
///     robot — the planner and the base controller — on the simulator's ground-truth pose
///     (or, with DriveConfig::odometry_yaml, on ucon-odometry's, as on the robot).
///     The planner's inputs come from ground truth (GroundTruthPerception: the movers as
///     tracks, the frame's returns off the movers as static points), so the route does not
///     depend on the perception under test: every method, and every later change to
///     perception, is scored on the same drive.
///  2. score: the recording's LIDAR_POINTS and ROBOT_POSE are replayed through each method's
///     perception node (its binding, as ucon-replay feeds it) and its PERCEPTION_OBJECTS are
///     scored with CLEAR-MOT against SIM_GROUND_TRUTH twice: every mover within the sensor's
///     crop range, and only the movers the sensor saw (visibility-aware: at least N returns on
///     the body in the frames the node was given; an occluded or too distant mover is neither
///     a miss nor, when a track sits on it, a false positive).
///
/// Nothing here reads the wall clock except the latency measurement, which is kept apart from
/// every other figure: the same scene, seed and configs give the same numbers on every run.

#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/mot/clear_mot.hpp"
#include "ucon/perception/detection.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/world/scenario.hpp"

namespace ucon {
namespace bench {

/// A planar robot pose [m, m, rad] with its velocity (world [m/s], yaw rate [rad/s]).
struct PlanarPose {
  double x = 0.0, y = 0.0, yaw = 0.0;
  double vx = 0.0, vy = 0.0, wz = 0.0;
};

/// Robot poses by time, interpolated per LiDAR point: linear in x, y and in yaw (along the
/// shorter arc); before the first pose the first is held, after the last it is extrapolated
/// with the last pose's velocity and yaw rate (a frame completes a few ms before the pose of
/// its last point is published).
class PoseTrack {
 public:
  /// Adds a valid pose; invalid, non-finite or not newer poses are ignored (false).
  bool add(const robot_pose_t& p);
  /// The pose at `utime` [us]; nullopt when no pose has been added.
  std::optional<PlanarPose> at(int64_t utime) const;
  /// Forgets poses older than `utime` [us] (keeps the last one before it).
  void dropBefore(int64_t utime);
  bool empty() const { return poses_.empty(); }

 private:
  std::deque<std::pair<int64_t, PlanarPose>> poses_;
};

/// Visibility test: the LiDAR returns of `cloud` (base frame, each point at utime + its
/// t_offset_ns, placed in the world with `poses`) that fall on each mover of `gt` — within
/// radius + `margin` [m] of its axis (the mover moved by its velocity to the point's time) and
/// between `min_z` [m] and height + `margin`. Returns mover id -> returns (movers with none
/// are absent).
std::map<int64_t, int> returnsOnMovers(const point_cloud_t& cloud, const PoseTrack& poses,
                                       const sim_ground_truth_t& gt, double margin = 0.15, double min_z = 0.1);

/// Events of a recording kept for scoring, in publication order.
struct RecordedEvent {
  std::string channel;
  std::vector<uint8_t> data;
};

/// What the drive itself was like (from ground truth).
struct DriveStats {
  double sim_s = 0.0;              ///< simulated seconds
  double path_m = 0.0;             ///< distance driven [m]
  double mean_speed = 0.0;         ///< path / time [m/s]
  double max_speed = 0.0;          ///< [m/s]
  double moving_share = 0.0;       ///< share of ground-truth frames with speed > 0.1 m/s
  double max_yaw_rate = 0.0;       ///< |wz| [rad/s] (ROBOT_POSE)
  int64_t collisions = 0;          ///< simulator's collision episodes
  int64_t goals_reached = 0;       ///< route goals reached
  /// Largest x-y distance of ROBOT_POSE from the simulator's pose at the same instant [m]
  /// (0 on ground truth; with DriveConfig::odometry_yaml the odometry's error).
  double pose_error_max = 0.0;
  uint64_t digest = 1469598103934665603ull;  ///< FNV-1a 64 of every recorded event (channel, bytes)
};

struct Recording {
  std::string scene;  ///< "pedestrians", "bench:80:3"
  int64_t seed = 0;
  std::vector<RecordedEvent> events;  ///< LIDAR_POINTS, ROBOT_POSE, SIM_GROUND_TRUTH
  DriveStats stats;
  /// The world driven through: its static obstacles classify false positives (empty: none).
  world::Scenario scenario;
};

/// Setup of one drive.
struct DriveConfig {
  simulator::SimulatorParams sim;
  lidar_driver::DriverParams driver;
  perception::PerceptionParams perception;  ///< crop and voxel of the ground-truth stand-in
  std::string planner_yaml, base_controller_yaml;  ///< node configs (YAML text)
  double duration_s = 60.0;        ///< simulated seconds, (0, 3600]
  double goal_tolerance = 0.4;     ///< a route goal is reached within this [m]
  std::string save_log;            ///< also write every event as an LCM log here ("" = no)
  /// The base controller's heading mode for the drive: "" as configured, "hold" (an
  /// omnidirectional base keeps its heading), "path" (it faces its velocity: turns at every
  /// goal and along curves, the sensor turning with it).
  std::string heading_mode;
  /// No route: the robot stays at its start (the control run: the same recording, scoring and
  /// methods with the sensor parked).
  bool parked = false;
  /// ucon-odometry's configuration (YAML text): when set, the odometry, started at the
  /// scenario's start, publishes ROBOT_POSE from the emulated Mid-360's points and IMU and the
  /// simulator publishes none, so the planner, the controller and the perception methods all
  /// run on the robot's own pose. Empty: the simulator's exact pose.
  std::string odometry_yaml;
};

/// Records one drive of `scenario`: the route is the scenario's goals and then its start,
/// again and again until duration_s. nullopt and `error` when a node cannot be made or the
/// log cannot be written.
std::optional<Recording> recordDrive(const DriveConfig& config, const world::Scenario& scenario,
                                     const std::string& scene, int64_t seed, std::string* error);

/// The perception parameters of a method: "ucon" (as shipped), "fapp" (FAPP-style
/// association), "ucon-noreassoc" (no point-level re-association). nullopt for another name.
std::optional<perception::PerceptionParams> methodParams(const std::string& method,
                                                         const perception::PerceptionParams& shipped);

/// How tracks are scored.
struct ScoreOptions {
  double threshold_m = 1.0;        ///< CLEAR-MOT x-y match distance [m]
  double max_range_m = 15.0;       ///< movers farther from the robot are not scored [m]
  int min_visible_points = 3;      ///< visibility-aware: fewer returns = not visible
  double velocity_range_m = 8.0;   ///< velocity error of matches within this of the robot [m]
  double static_fp_distance = 0.5; ///< a false positive this near a static footprint is on it [m]
  std::FILE* trace = nullptr;      ///< if set: one line per identity switch, visible miss (with its cause),
                                   ///< visibility-aware false positive and velocity error above 0.5 m/s
  std::string trace_label;         ///< first word of each trace line (scene and seed)
};

/// Why a visible mover was missed in a scored frame, judged from the node's own clusters and
/// published objects of that frame (first cause that applies, in this order).
enum MissCause : int {
  kMissTrackTaken = 0,    ///< a confirmed or coasting track lies within the threshold but was matched to another mover
  kMissNoCluster,         ///< no cluster within kMissClusterDistance of its centre (too few returns, or cropped)
  kMissNotObject,         ///< its cluster is too large or too flat for one object (merged into structure)
  kMissHidden,            ///< object-sized but failed the motion test, most points undecided: the reference saw
                          ///< only returns well in front of them (an occluder, often another mover)
  kMissOnReference,       ///< failed the motion test, most points near reference points (slow, or on its own trail)
  kMissMotionOther,       ///< failed the motion test otherwise (surface seen at its range, or no reference yet)
  kMissTentative,         ///< dynamic, and a tentative track lies within the threshold
  kMissNoTrack,           ///< dynamic, and no track lies within the threshold
  kMissCauses
};
constexpr double kMissClusterDistance = 0.3;  ///< [m] a cluster's x-y box this close to a mover's centre is its cluster
constexpr int kMissRangeBands = 4;            ///< range bands of the miss counts [m]: < 6, 6-9, 9-12, >= 12

/// Short name of a cause (JSON keys, printed tables).
const char* missCauseName(MissCause cause);

/// Range band of a mover `range_m` from the robot.
int missRangeBand(double range_m);

/// The cause of a miss of the mover at `xy` [m], from the node's detections of the frame and
/// the objects it published for it (threshold_m: the CLEAR-MOT match distance).
MissCause classifyMiss(const Eigen::Vector2d& xy, const std::vector<perception::Detection>& detections,
                       const tracked_objects_t& objects, double threshold_m);

/// One method's figures on one recording.
struct MethodScore {
  std::string method;
  mot::ClearMotSummary all;      ///< every mover within max_range_m
  mot::ClearMotSummary visible;  ///< only movers with >= min_visible_points returns
  int64_t frames = 0, invalid_frames = 0;
  double velocity_error_median = NAN;  ///< visible matches within velocity_range_m [m/s]
  double velocity_error_p90 = NAN;
  double velocity_error_over = NAN;    ///< share off by more than 0.5 m/s
  double latency_median_ms = NAN;      ///< wall time of a LIDAR_POINTS feed (noisy)
  double latency_p99_ms = NAN;
  int64_t track_ids = 0;               ///< distinct confirmed track ids published
  /// Visibility-aware false positives per frame by the robot's motion at the frame:
  /// [speed bin][yaw-rate bin] -> {frames, false positives}. Speed bins [m/s]: < 0.1, < 0.75,
  /// >= 0.75; yaw-rate bins [rad/s]: < 0.2, < 0.6, >= 0.6.
  int64_t fp_frames[3][3] = {};
  int64_t fp_count[3][3] = {};
  uint64_t output_digest = 1469598103934665603ull;  ///< FNV-1a 64 of every PERCEPTION_OBJECTS
  /// Where the visibility-aware false positives are: within `static_fp_distance` of a static
  /// obstacle's footprint (per obstacle index of Recording::scenario.statics), else within
  /// 1.5 m of a mover (a split, a lagging or a doubled track), else elsewhere.
  int64_t fp_on_static = 0, fp_near_mover = 0, fp_elsewhere = 0;
  std::map<int, int64_t> fp_per_static;
  /// What the tracks behind the false positives on static structure are: distinct ids, and
  /// medians over those false positives of the track's age [frames], its reported speed [m/s],
  /// and the share that was not measured in that frame (coasting on a prediction).
  int64_t fp_static_tracks = 0;
  double fp_static_age_median = NAN;
  double fp_static_speed_median = NAN;
  double fp_static_coasting_share = NAN;
  /// Visibility-aware misses by cause (MissCause) and range band of the mover (missRangeBand).
  int64_t miss_causes[kMissCauses][kMissRangeBands] = {};
  /// What the sensor allowed, over the object-frames of `all` (every scored mover in every
  /// published output): those with at least min_visible_points returns in that output's
  /// frames (`visible`), with at least kWellSeenPoints (`well_seen`), with enough returns in
  /// that output or in one at most the method's max_coast before it (`held`: what a tracker
  /// that coasts as long as this one can hold at best), and in that output or any earlier one
  /// (`seen`). A tracker knows nothing of a mover it has never seen, so the plain MOTA cannot
  /// exceed seen / objects, whatever the method. `predictable`: visible, or seen before and
  /// within the match distance of where its last view puts it now, at that view's true
  /// velocity or at rest (the better of the two): what a tracker that knew each mover exactly
  /// when it last saw it, and kept hidden ones at constant velocity or in place for as long as
  /// needed, could match at best.
  struct SensorShare {
    int64_t objects = 0, visible = 0, well_seen = 0, held = 0, seen = 0, predictable = 0;
    SensorShare& operator+=(const SensorShare& o) {
      objects += o.objects, visible += o.visible, well_seen += o.well_seen, held += o.held, seen += o.seen;
      predictable += o.predictable;
      return *this;
    }
  } sensor;
};
constexpr int kWellSeenPoints = 10;  ///< returns on a mover in a frame that make it well seen

/// Replays `rec` through a perception node per method (`params` in the same order as
/// `methods`) and scores each. Throws std::runtime_error on an undecodable recorded event.
std::vector<MethodScore> scoreRecording(const Recording& rec, const std::vector<std::string>& methods,
                                        const std::vector<perception::PerceptionParams>& params,
                                        const ScoreOptions& options);

/// The adapter the scorer replays a method through: the perception node's binding, exactly
/// as ucon-replay --node perception feeds it.
std::unique_ptr<replay::NodeAdapter> makePerceptionReplay(const perception::PerceptionParams& params);

}  // namespace bench
}  // namespace ucon
