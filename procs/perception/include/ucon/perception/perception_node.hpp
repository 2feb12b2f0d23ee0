#pragma once
/// @file perception_node.hpp
/// The perception node: LiDAR frames + robot poses -> tracked dynamic objects with full
/// covariance, static points and status (paper Sec. III and IV-A). No sockets, no wall clock
/// in the logic: "now" is the frames' utime. Stage timings use an injectable stopwatch and go
/// to the status only, so outputs are byte-identical between runs.
///
/// The pipeline, per frame, one module per stage:
///  1. preprocess.hpp: world frame with the pose interpolated at the frame time, range/height
///     crop, the last `accumulate_frames` frames merged, voxel grid;
///  2. detection.hpp: Euclidean clusters; an object-sized cluster is dynamic if it moved
///     (motion_test.hpp: FAPP-style, points with no neighbour in frames 0.5-1.0 s old, vetoed
///     where the old scans did not see past them) or a live track predicts it;
///  3. association.hpp: eq. 1 + Hungarian (or the greedy FAPP baseline); measurement.hpp: the
///     matched points' centre, box and width;
///  4. reassociation.hpp: the appendix algorithm for the tracks left unmatched, and its
///     conflicts with the object-level matches;
///  5. track_manager.hpp: the Kalman filter (common/kalman) and the track lifecycle
///     (tentative -> confirmed -> coasting -> deleted, negative evidence, re-identification);
///  6. outputs.hpp: PERCEPTION_OBJECTS and PERCEPTION_STATIC (points whose x-y cell has been
///     occupied for static_persistence, static_persistence.hpp).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ucon/message_clock.hpp"
#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/detection.hpp"
#include "ucon/perception/measurement.hpp"
#include "ucon/perception/motion_test.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/pose_buffer.hpp"
#include "ucon/perception/preprocess.hpp"
#include "ucon/perception/proximity_index.hpp"
#include "ucon/perception/static_persistence.hpp"
#include "ucon/perception/track_manager.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/status_report.hpp"
#include "ucon/tracked_objects_t.hpp"

namespace ucon {
namespace perception {

/// What a handler asks the process to publish.
struct PerceptionOutput {
  std::optional<tracked_objects_t> objects;      ///< PERCEPTION_OBJECTS
  std::optional<static_points_t> static_points;  ///< PERCEPTION_STATIC
};

/// The node.
class PerceptionNode {
 public:
  /// Seconds from an arbitrary origin; used only to time the stages for the status.
  using Stopwatch = std::function<double()>;

  /// `stopwatch` empty = std::chrono::steady_clock.
  explicit PerceptionNode(const PerceptionParams& params, Stopwatch stopwatch = {});

  /// ROBOT_POSE. Invalid, non-finite or out-of-order poses are counted and dropped.
  void onPose(const robot_pose_t& pose);

  /// LIDAR_POINTS. Returns the outputs of this frame (nothing for a dropped frame:
  /// repeated, older than the last one, bad utime or malformed arrays).
  PerceptionOutput onPoints(const point_cloud_t& cloud);

  /// Periodic check at message time `utime` [us] (the newest input time): when no frame has
  /// arrived for frame_timeout, returns an invalid PERCEPTION_OBJECTS (once per timeout).
  PerceptionOutput tick(int64_t utime);

  /// Counters, stage timings [ms] and gauges for PERCEPTION_STATUS.
  StatusReport& status() { return status_; }
  /// Newest input time [us] (frames and poses).
  int64_t now() const { return clock_.now(); }
  /// Total processing time of the last processed frame [ms].
  double lastFrameMs() const { return last_frame_ms_; }
  /// Detections of the last processed frame (for tests and diagnostics).
  const std::vector<Detection>& lastDetections() const { return detections_; }
  /// Pre-processed points of the last processed frame, world frame.
  const Points& lastPoints() const { return frame_.points; }

 private:
  /// What stages 3-4 decided for the tracks that existed before this frame.
  struct Assignment;
  PerceptionOutput invalidOutput(int64_t utime, int64_t frame_seq, const std::string& why);
  void associate(const std::vector<int>& dynamic, const std::vector<TrackView>& views, Assignment* a);
  void recover(const std::vector<int>& dynamic, const std::vector<TrackView>& views, Assignment* a);
  /// The tracks other than j whose objects merged into the cluster of these frame points (with
  /// UCON's association and object_association.split_shared on): not tentative, seen within
  /// cascade_after, matched to no cluster, predicted within 0.1 m of the cluster's x-y bounds;
  /// none unless j and they have a settled velocity (velocitySettled()).
  std::vector<int> sharingTracks(const std::vector<int>& indices, int j, const Matching& match,
                                 const std::vector<TrackView>& views) const;
  void startTracks(const std::vector<int>& dynamic, Assignment* a);
  /// Whether at least tracks.structure_share of these frame points lie on x-y cells occupied
  /// without a gap since structure_margin before `since` [us] (when the track came to its place,
  /// or was created): what the track measures stood there before the track came.
  bool onStructure(const std::vector<int>& points, int64_t since) const;
  double elapsedMs(double since) const { return (stopwatch_() - since) * 1e3; }

  PerceptionParams params_;
  Stopwatch stopwatch_;
  MessageClock clock_;
  PoseBuffer poses_;
  StatusReport status_;
  AngularGrid fine_grid_;    ///< the motion test's bins (segmentation.free_space_bin_deg)
  AngularGrid coarse_grid_;  ///< the "seen through" bins (tracks.free_bin_deg)
  Preprocessor preprocessor_;
  MotionTest motion_;
  Detector detector_;
  Measurer measurer_;
  TrackManager tracks_;
  StaticPersistence persistence_;  ///< x-y cells occupied long enough for PERCEPTION_STATIC
  std::vector<char> persistent_;   ///< per frame point: its cell passed the persistence test
  ProximityIndex frame_index_;     ///< grid over the frame's points (cells of d0), built only when re-association runs

  Frame frame_;                     ///< the frame being (or last) processed
  std::vector<Detection> detections_;
  int64_t last_frame_utime_ = 0;
  int64_t last_output_utime_ = 0;   ///< last time outputs were published (frames or tick)
  int64_t objects_seq_ = 0;
  int64_t static_seq_ = 0;
  double last_frame_ms_ = 0.0;
};

}  // namespace perception
}  // namespace ucon
