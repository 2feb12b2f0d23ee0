#pragma once
/// @file perception_node.hpp
/// The perception node: LiDAR frames + robot poses -> tracked dynamic objects with full
/// covariance, static points and status (paper Sec. III and IV-A; issue 4). No sockets, no
/// wall clock in the logic: "now" is the frames' utime. Stage timings use an injectable
/// stopwatch and go to the status only, so outputs are byte-identical between runs.
///
/// Per frame: (1) world frame with the pose interpolated at the frame time, range/height
/// crop, the last `accumulate_frames` frames merged, PCL voxel grid; (2) PCL Euclidean
/// clustering; an object-sized cluster is dynamic if it moved (FAPP-style: share of points
/// with no KD-tree neighbour in frames 0.5-1.0 s old, vetoed where the old scan did not see
/// past the point, i.e. disocclusion) or a live track predicts it; (3) eq. 1 + Hungarian
/// (or the greedy FAPP baseline); (4) appendix re-association for the tracks left unmatched;
/// (5) track states tentative -> confirmed -> coasting -> deleted, with negative evidence
/// (a track the sensor sees through is deleted) and re-identification of a recently lost
/// confirmed track; (6) the common/kalman filter (position + differenced velocity).

#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/message_clock.hpp"
#include "ucon/perception/association.hpp"
#include "ucon/perception/euclidean_clusters.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/point_index.hpp"
#include "ucon/perception/pose_buffer.hpp"
#include "ucon/perception/proximity_index.hpp"
#include "ucon/perception/static_persistence.hpp"
#include "ucon/point_cloud_t.hpp"
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

/// One detected cluster of the current frame.
struct Detection {
  std::vector<int> indices;  ///< into the frame's pre-processed points
  BoxXY box;
  double min_z = 0.0, max_z = 0.0, mean_z = 0.0;  ///< [m]
  bool size_ok = false;    ///< object-sized
  bool moving = false;     ///< passed the motion test
  bool supported = false;  ///< near a live track's prediction
  bool dynamic() const { return size_ok && (moving || supported); }
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
  /// repeated, older than the last one, bad utime or frame_id).
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
  const std::vector<Detection>& lastDetections() const { return last_detections_; }
  /// Pre-processed points of the last processed frame, world frame.
  const Points& lastPoints() const { return frame_points_; }

 private:
  struct Track {
    int64_t id = 0;
    int8_t state = 0;
    int8_t last_association = 0;
    kalman::ConstantVelocityKalman kf;
    int64_t created_utime = 0;
    int64_t last_seen_utime = 0;  ///< last measurement
    Eigen::Vector2d seen_velocity = Eigen::Vector2d::Zero();  ///< filtered x-y velocity right after it [m/s]
    int hits = 0;
    int misses = 0;               ///< consecutive frames without a measurement
    int age_frames = 0;
    int consecutive_reassoc = 0;
    bool confirmed_once = false;  ///< was confirmed at some point
    bool reidentified = false;    ///< handed its identity to a new track
    int free_count = 0;           ///< consecutive frames an unseen track was seen through
    int moving_hits = 0;          ///< measurements from clusters that passed the motion test
    int64_t last_moving_utime = 0;  ///< last such measurement
    int64_t last_fast_utime = 0;    ///< last frame its filtered speed reached confirm_min_speed
    int num_points = 0;           ///< points of the latest measurement
    Eigen::Vector2d size = Eigen::Vector2d::Zero();
    double size_z = 0.0;
    double width = 0.0;           ///< extent across the line of sight in views not cut by an occluder [m]; 0 = none yet
    Eigen::Vector2d first_center = Eigen::Vector2d::Zero();  ///< where it was first measured [m]
    Points history;               ///< T_c: the latest measurement's points (thinned)
    struct Measured {
      int64_t utime = 0;
      Eigen::Vector3d center = Eigen::Vector3d::Zero();
      Points points;  ///< thinned; empty unless tracks.registration_velocity
    };
    std::deque<Measured> measured;  ///< the measurements of the last velocity baseline
    explicit Track(const kalman::KalmanParams& p) : kf(p) {}
  };
  /// Motion-test history: consecutive frames merged into chunks of ~history_chunk seconds,
  /// each indexed once when it closes (a few KD-tree queries per point instead of one per
  /// frame; the test only asks whether any reference point lies near, see ProximityIndex).
  struct HistoryChunk {
    int64_t first_utime = 0;
    int64_t last_utime = 0;
    Points points;
    ProximityIndex index;
    bool closed = false;
    Eigen::Vector3f origin = Eigen::Vector3f::Zero();  ///< sensor origin of its first frame [m]
    std::vector<float> max_range;  ///< farthest return per angular bin seen from origin [m]; 0 = none
  };
  int angularBin(const Eigen::Vector3f& d) const;
  struct Measurement {
    Eigen::Vector3d center;
    BoxXY box;
    double size_z = 0.0;
    Points points;
    double width = 0.0;     ///< extent across the line of sight [m]
    bool occluded = false;  ///< something nearer lies just beyond an edge across the line of sight
    bool cut = false;       ///< one side hidden and the view narrower than the track: centred from the other edge
  };

  PerceptionOutput invalidOutput(int64_t utime, int64_t frame_seq, const std::string& why);
  void preprocess(const point_cloud_t& cloud, const Eigen::Isometry3d& T);
  void segment();
  void predictTracks(int64_t utime);
  std::vector<TrackView> trackViews(int64_t utime) const;
  /// The measurement of a cluster's points; with the track they are for, a view cut on one
  /// side by a nearer occluder is centred from its other, visible edge and the track's width.
  Measurement measure(const std::vector<int>& indices, const Track* track = nullptr) const;
  /// Whether something nearer than the points lies just beyond their edge across the line of
  /// sight, on the side of +n (hi) or -n (lo).
  bool edgeOccluded(const std::vector<int>& indices, const Eigen::Vector2d& n, bool hi) const;
  void applyMeasurement(Track& t, const Measurement& m, int64_t utime, int8_t how, bool moving);
  /// Share of `indices` that failed the motion test (moved).
  double movedShare(const std::vector<int>& indices) const;
  std::vector<int> restrictToTrack(const Track& t, const std::vector<int>& indices) const;
  void manageTracks(int64_t utime, const std::vector<char>& updated);
  void reidentify(Track& fresh, int64_t utime);
  tracked_objects_t buildObjects(int64_t utime, int64_t frame_seq) const;
  static_points_t buildStatic(int64_t utime, const Eigen::Isometry3d& T,
                              const std::vector<char>& dynamic_point) const;
  void pushHistory(int64_t utime, const std::vector<char>& tracked_point);
  double elapsedMs(double since) const { return (stopwatch_() - since) * 1e3; }

  PerceptionParams params_;
  Stopwatch stopwatch_;
  MessageClock clock_;
  PoseBuffer poses_;
  StaticPersistence persistence_;  ///< x-y cells occupied long enough for PERCEPTION_STATIC
  std::vector<char> persistent_;   ///< per frame point: its cell passed the persistence test
  StatusReport status_;

  int64_t last_frame_utime_ = 0;
  int64_t last_processed_utime_ = 0;  ///< time all track filters refer to
  double last_dt_ = 0.0;              ///< time since the previous processed frame [s]
  int64_t last_output_utime_ = 0;   ///< last time outputs were published (frames or tick)
  int64_t objects_seq_ = 0;
  int64_t static_seq_ = 0;
  int64_t next_track_id_ = 1;
  std::vector<Track> tracks_;       ///< ordered by creation
  /// Confirmed tracks deleted recently, kept for re-identification.
  struct LostTrack {
    int64_t id = 0;
    int age_frames = 0;
    Eigen::Vector2d last_center = Eigen::Vector2d::Zero();
    Eigen::Vector2d seen_velocity = Eigen::Vector2d::Zero();
    int64_t last_seen_utime = 0;
  };
  std::deque<LostTrack> lost_tracks_;
  std::deque<HistoryChunk> history_;

  Eigen::Vector2d last_robot_xy_ = Eigen::Vector2d::Zero();  ///< robot position of the frame [m]
  Eigen::Vector3f sensor_origin_ = Eigen::Vector3f::Zero();   ///< sensor origin of the frame, world [m]
  Eigen::Vector3d sensor_origin_d_ = Eigen::Vector3d::Zero();  ///< the same in double (static output)
  int az_bins_ = 360, el_bins_ = 180;
  int free_az_ = 120, free_el_ = 60;
  std::vector<float> frame_min_range_;  ///< nearest return per coarse bin of this frame [m]; inf = none
  std::vector<float> frame_fine_min_range_;  ///< nearest return per motion-test bin of this frame [m]; inf = none
  bool pointMoved(const Eigen::Vector3f& p, const std::vector<const HistoryChunk*>& chunks) const;
  int freeBin(const Eigen::Vector3f& d) const;
  std::deque<Points> recent_cropped_;  ///< cropped world points of the last frames (accumulation)
  Points frame_returns_;  ///< every return of the newest frame outside the robot's body, ground and far ones included: free-space evidence
  Points frame_points_;             ///< pre-processed, world frame
  std::vector<char> point_moved_;   ///< per frame point: failed the motion test (moved)
  EuclideanClusterer clusterer_;    ///< clustering with reused scratch buffers
  ProximityIndex frame_index_;      ///< grid over frame_points_ (cells of d0), built only when re-association runs
  std::vector<Detection> last_detections_;
  double last_frame_ms_ = 0.0;
};

}  // namespace perception
}  // namespace ucon
