#pragma once
/// @file preprocess.hpp
/// Stage 1 of the pipeline: a LiDAR frame in the world frame, cropped to the space objects
/// occupy, merged with the previous frame(s) and voxel down-sampled; with the nearest return
/// in each direction, which the later stages use as free-space evidence.

#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Geometry>

#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/point_index.hpp"
#include "ucon/perception/pose_buffer.hpp"
#include "ucon/point_cloud_t.hpp"

namespace ucon {
namespace perception {

/// One processed frame and what the stages learn about its points.
struct Frame {
  int64_t utime = 0;                                          ///< frame time [us]
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();     ///< robot (base) to world at utime
  Eigen::Vector2d robot_xy = Eigen::Vector2d::Zero();         ///< robot position [m]
  Eigen::Vector3f sensor_origin = Eigen::Vector3f::Zero();    ///< sensor origin, world [m]
  Eigen::Vector3d sensor_origin_d = Eigen::Vector3d::Zero();  ///< the same in double (static output)
  /// Every return of the newest frame outside the robot's body, ground and far ones included:
  /// the space their rays crossed was free (world [m]).
  Points returns;
  Points points;  ///< pre-processed: cropped, the last frames merged, voxel down-sampled (world [m])
  /// Nearest return (`points` and `returns`) per bin of the motion-test grid [m]; inf = none.
  std::vector<float> nearest_fine;
  /// Nearest pre-processed point per bin of the "seen through" grid [m]; inf = none.
  std::vector<float> nearest_coarse;
  std::vector<char> moved;  ///< per point of `points`: failed the motion test (set by detection)
};

class Preprocessor {
 public:
  /// `fine`: the motion test's bins (segmentation.free_space_bin_deg); `coarse`: the bins of the
  /// "seen through" check of unseen tracks (tracks.free_bin_deg).
  Preprocessor(const PreprocessParams& params, const AngularGrid& fine, const AngularGrid& coarse);

  /// What one frame's pre-processing counted.
  struct Result {
    int64_t non_finite = 0;        ///< points dropped for a non-finite coordinate
    bool pose_extrapolated = false;  ///< the frame's last point is later than the newest pose
  };

  /// Places a pose's time offsets [us] are sampled at: a point takes the pose of the nearest
  /// sample, so its placement is off by at most half of this times the speed (0.1 mm at 1 m/s).
  static constexpr int64_t kPoseStepUs = 200;
  /// Time offsets are clamped to the frame's duration_us and to this [us] (a 10 Hz frame is 100 ms).
  static constexpr int64_t kMaxSpanUs = 500'000;

  /// Fills `frame` from a cloud in the base frame (or already in the world frame). Each point
  /// is placed in the world with the robot's pose at its own time (utime + t_offset_ns; a
  /// cloud without offsets, with one pose): a driving or turning sensor's frame is not smeared
  /// over the 20 ms it takes. `pose` is the pose at the frame's utime (frame.pose); `poses`
  /// gives the pose within the frame, extrapolated past the newest pose up to `max_gap_s` [s]
  /// (PoseBuffer::at; beyond it the last pose found is held). Non-finite points are dropped.
  Result process(const point_cloud_t& cloud, const Eigen::Isometry3d& pose, const PoseBuffer& poses,
                 double max_gap_s, Frame* frame);

 private:
  PreprocessParams params_;
  std::vector<Eigen::Matrix3f> knot_rotation_;     ///< the pose every kPoseStepUs across the frame
  std::vector<Eigen::Vector3f> knot_translation_;
  AngularGrid fine_, coarse_;
  std::deque<Points> recent_cropped_;  ///< cropped world points of the last frames (accumulation)
};

}  // namespace perception
}  // namespace ucon
