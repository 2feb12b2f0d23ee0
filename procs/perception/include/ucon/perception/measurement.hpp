#pragma once
/// @file measurement.hpp
/// What a cluster's points say about a tracked object: the measured centre, box and width
/// across the line of sight, corrected for the side of the object the sensor cannot see and
/// for an occluder cutting the view on one side; and which of a merged cluster's points belong
/// to the track.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/association.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/preprocess.hpp"

namespace ucon {
namespace perception {

/// One measurement of an object.
struct Measurement {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< x-y: box centre (corrected), z: mean height [m]
  BoxXY box;                ///< corrected centre and x-y extent [m]
  double size_z = 0.0;      ///< z extent [m]
  Points points;            ///< the points measured (world [m])
  double width = 0.0;       ///< extent across the line of sight [m]
  bool occluded = false;    ///< something nearer lies just beyond an edge across the line of sight
  bool cut = false;         ///< one side hidden and the view narrower than the track: centred from the other edge
};

/// Measures tracked objects on one frame.
class Measurer {
 public:
  /// `grid`: the motion test's angular bins (segmentation.free_space_bin_deg), over which
  /// frame.nearest_fine is kept.
  Measurer(const SegmentationParams& params, const AngularGrid& grid);

  /// The measurement of the points `indices` (not empty) of `frame`: the box centre is moved
  /// away from the sensor for an object seen from one side (view_center_shift, footprint.hpp).
  /// For a track (`track_width`: its width from uncut views, 0 = none yet), a view cut on one
  /// side by a nearer occluder and narrower than the track by occlusion_anchor is centred half
  /// the track's width from its visible edge; a new object has no width to place.
  Measurement measure(const Frame& frame, const std::vector<int>& indices,
                      std::optional<double> track_width = std::nullopt) const;

 private:
  /// Whether something nearer than the points lies just beyond their edge across the line of
  /// sight, on the side of +n (hi) or -n (lo).
  bool edgeOccluded(const Frame& frame, const std::vector<int>& indices, const Eigen::Vector2d& n, bool hi) const;

  SegmentationParams params_;
  AngularGrid grid_;
};

/// The points of a matched cluster that measure the track predicted at `center` with box
/// `size` [m]: all of them, unless the cluster is larger than the track's box by `margin` in
/// x or y (the object merged with a pillar it brushes, or another person); then those inside
/// the predicted box grown by the margin, of those the ones that moved (`moved`, per frame
/// point) when there are at least 3, else the inside ones when at least 3, else all.
std::vector<int> restrictToTrack(const Points& points, const std::vector<char>& moved, const Eigen::Vector2d& center,
                                 const Eigen::Vector2d& size, double margin, const std::vector<int>& indices);

/// `indices` split by the nearest of `centers` in x-y (ties to the first): part k holds the
/// points nearer to centers[k] than to any other centre. Objects merged into one cluster.
std::vector<std::vector<int>> splitByNearest(const Points& points, const std::vector<int>& indices,
                                             const std::vector<Eigen::Vector2d>& centers);

/// Share of `indices` marked in `moved` (0 for none).
double movedShare(const std::vector<char>& moved, const std::vector<int>& indices);

}  // namespace perception
}  // namespace ucon
