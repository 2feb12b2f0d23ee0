#pragma once
/// @file convert.hpp
/// ucon LCM messages -> Foxglove well-known messages (JSON), the pure core shared by
/// ucon-mcap and ucon-foxglove-bridge. No I/O: messages in, JSON texts out.
///
/// Topics written for a message on LCM channel C (c = C in lower case):
///   point_cloud_t      -> /c              foxglove.PointCloud (x, y, z, reflectivity, tag)
///   static_points_t    -> /c              foxglove.PointCloud (x, y, z), and the accumulated
///                         static map       /map  foxglove.Grid, every map_period_s of message time
///   robot_pose_t       -> /tf             foxglove.FrameTransform world -> base
///                         /c              foxglove.PoseInFrame
///   sim_ground_truth_t -> /tf             foxglove.FrameTransform world -> base_truth
///                         /c/pose         foxglove.PoseInFrame
///                         /c/objects      foxglove.SceneUpdate (true obstacles and robot)
///   tracked_objects_t  -> /c              foxglove.SceneUpdate: per track a cylinder, the
///                         n-sigma covariance ellipse, the velocity arrow, the id, and the
///                         uncertainty sector of paper eqs. 6-7 as a triangle fan
///   trajectory_t       -> /c              foxglove.SceneUpdate: the trajectory as a line strip
///   nav_goal_t         -> /c              foxglove.PoseInFrame
///   process_status_t   -> /c              ucon.StatusView: timings, counters and gauges as
///                         {name, value} arrays, for plots (planning time, perception latency)
/// Every other ucon type has no Foxglove view (its raw JSON topic is the one to plot).

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon {
namespace foxglove {

struct LcmTypeInfo;

/// What the Foxglove views are drawn with. The sector, the body radius and the map band are
/// the planner's (deploy/config/planner.yaml), so that what Foxglove shows is what it plans
/// around.
struct ViewParams {
  trajopt::OptimizerParams optimizer;   ///< planner.yaml `optimizer` (sector h, k, kappa, s, model)
  kalman::KalmanParams prediction;      ///< planner.yaml `prediction` (process noise; the rest unused)
  double min_radius = 0.3;              ///< planner.yaml objects.min_radius: smallest body radius [m]
  double map_resolution = 0.1;          ///< planner.yaml map.resolution: static map cell [m]
  double band_z_min = 0.1;              ///< planner.yaml map.band_z_min: static points in the map band [m]
  double band_z_max = 0.6;              ///< planner.yaml map.band_z_max [m]
  double sigma = 2.0;                   ///< covariance ellipses at this many standard deviations [-], > 0
  double map_period_s = 1.0;            ///< the static map is written this often (message time) [s], > 0
  double trajectory_step_s = 0.05;      ///< trajectory line sampled this often [s], > 0
  int max_map_cells = 4 << 20;          ///< larger maps are cut to this many cells around the latest points [-]
};

/// Reads ViewParams from the text of a planner.yaml. nullopt and *error (naming the key) when
/// a key it needs is missing or out of range.
std::optional<ViewParams> viewParamsFromPlannerYaml(const std::string& yaml, const std::string& source,
                                                    std::string* error);

/// A Foxglove topic these tools write.
struct FoxgloveTopic {
  std::string topic;        ///< "/lidar_points"
  std::string schema_name;  ///< "foxglove.PointCloud"
  bool operator<(const FoxgloveTopic& o) const {
    return topic < o.topic || (topic == o.topic && schema_name < o.schema_name);
  }
};

/// The Foxglove topics a message of `type_name` on `channel` is converted to (empty when the
/// type has no Foxglove view).
std::vector<FoxgloveTopic> foxgloveTopicsFor(const std::string& channel, const std::string& type_name);

/// One converted message.
struct FoxgloveMessage {
  FoxgloveTopic topic;
  std::string json;
};

/// Counters of what could not be drawn.
struct ConvertStats {
  int64_t objects_skipped = 0;       ///< tracks or obstacles with non-finite position or size
  int64_t ellipses_skipped = 0;      ///< covariance missing, non-finite or not positive definite
  int64_t sectors_skipped = 0;       ///< planner's sector model rejected the track
  int64_t trajectories_invalid = 0;  ///< trajectory messages that do not describe a trajectory
  int64_t points_skipped = 0;        ///< non-finite points (not written)
  int64_t map_points_clipped = 0;    ///< static points outside the map window
};

/// Converts messages in arrival order. Holds the static map accumulated so far.
class FoxgloveConverter {
 public:
  explicit FoxgloveConverter(const ViewParams& params);

  /// Converts one encoded message of `type` on `channel` whose time is `utime` [us] (the
  /// caller's time policy: the message's own utime, or the clock for untimed messages).
  /// Appends the Foxglove messages to *out; returns false when the bytes do not decode.
  bool convert(const std::string& channel, const LcmTypeInfo& type, const void* data, std::size_t size,
               int64_t utime, std::vector<FoxgloveMessage>* out);

  /// The static map as it is now (nothing when no static point was seen, or, with
  /// `only_if_changed`, when no point was added since it was last written).
  void flushMap(int64_t utime, bool only_if_changed, std::vector<FoxgloveMessage>* out);

  const ConvertStats& stats() const { return stats_; }
  const ViewParams& params() const { return params_; }

 private:
  void addMapPoints(const std::vector<float>& x, const std::vector<float>& y, const std::vector<float>& z);

  ViewParams params_;
  ConvertStats stats_;
  std::unordered_map<uint64_t, uint32_t> map_hits_;  ///< cell (ix, iy) -> static points in the band
  int64_t next_map_utime_ = 0;
  bool map_dirty_ = false;
  int32_t last_cx_ = 0, last_cy_ = 0;  ///< cell of the latest static points (the window's centre)
  std::string scratch_;
};

}  // namespace foxglove
}  // namespace ucon
