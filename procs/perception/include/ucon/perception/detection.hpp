#pragma once
/// @file detection.hpp
/// Stage 2 of the pipeline: the frame's points clustered into objects, each classified as
/// dynamic when it is object-sized and either moved (motion_test.hpp) or lies where a live track
/// predicts an object.

#include <vector>

#include <Eigen/Core>

#include "ucon/perception/association.hpp"
#include "ucon/perception/euclidean_clusters.hpp"
#include "ucon/perception/motion_test.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/preprocess.hpp"

namespace ucon {
namespace perception {

/// One detected cluster of the current frame.
struct Detection {
  std::vector<int> indices;  ///< into the frame's pre-processed points
  BoxXY box;                 ///< view-corrected centre (footprint.hpp), x-y extent [m]
  double min_z = 0.0, max_z = 0.0, mean_z = 0.0;  ///< [m]
  bool size_ok = false;    ///< object-sized
  bool moving = false;     ///< passed the motion test
  bool supported = false;  ///< near a live track's prediction
  MotionEvidence evidence;  ///< what the motion test found (object-sized clusters with a reference)
  bool dynamic() const { return size_ok && (moving || supported); }
};

class Detector {
 public:
  explicit Detector(const SegmentationParams& params);

  /// Euclidean clusters of the frame's points (cluster_tolerance, min/max_cluster_points).
  const std::vector<std::vector<int>>& cluster(const Frame& frame);

  /// Describes the clusters of the last cluster() call and runs the motion test on them
  /// (marking frame->moved); `predicted` holds the live tracks' predicted x-y centres [m].
  /// A cluster too large for one object but at most split_max_size gives its moved points,
  /// clustered on their own, as objects of their own (listed before it); `split_parts` counts them.
  std::vector<Detection> classify(Frame* frame, const MotionTest& motion,
                                  const std::vector<Eigen::Vector2d>& predicted, int* split_parts);

 private:
  Detection describe(const Frame& frame, const std::vector<int>& indices,
                     const std::vector<Eigen::Vector2d>& predicted) const;

  SegmentationParams params_;
  EuclideanClusterer clusterer_;  ///< clustering with reused scratch buffers
  std::vector<std::vector<int>> groups_;
  Points far_points_;            ///< scratch: unclustered points beyond far_cluster_range
  std::vector<int> far_index_;   ///< ... and their indices in the frame
  std::vector<char> far_used_;   ///< scratch: per frame point, taken by a first-pass cluster
};

}  // namespace perception
}  // namespace ucon
