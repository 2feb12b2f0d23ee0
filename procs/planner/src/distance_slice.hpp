#pragma once
/// @file distance_slice.hpp
/// The planner map's 2-D signed distance slice: the 3-D tree's height band projected onto one
/// layer (a cell is occupied when any cell of the band above it is), a DynamicEDT3D distance
/// transform of that layer over a box around the robot (incremental from the projection's
/// change detection; rebuilt when the robot leaves the box's centre region), and the cached
/// slice of signed distances the optimiser interpolates. Projecting first keeps the
/// transform's cost independent of the band's height; the distance of a point to the band's
/// obstacles is the 2-D distance to that projection. Private to ucon_planner_map.

#include <dynamicEDT3D/dynamicEDTOctomap.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "leaf_cache.hpp"
#include "ucon/planner/esdf_map.hpp"

namespace ucon::planner {

class DistanceSlice {
 public:
  /// `leaves`: the 3-D map the slice projects (it must outlive the slice).
  DistanceSlice(const MapParams& params, LeafCache& leaves);
  DistanceSlice(const DistanceSlice&) = delete;
  DistanceSlice& operator=(const DistanceSlice&) = delete;

  /// EsdfMap::update: projects the 3-D changes, then updates the distance transform around
  /// `robot_xy` (incrementally, or a fresh box when the robot left the centre region or
  /// `force_rebuild`) and the slice. True when the box was rebuilt.
  bool update(const Eigen::Vector2d& robot_xy, bool force_rebuild);
  bool ready() const { return edt_ != nullptr; }

  /// EsdfMap::distance: bilinear between cell centres, exact gradient of the interpolant.
  double distance(double x, double y, Eigen::Vector2d* grad) const {
    const SliceGeometry& s = geometry_;
    if (!edt_ || s.nx < 2 || s.ny < 2 || !std::isfinite(x) || !std::isfinite(y)) {
      if (grad) grad->setZero();
      return params_.max_distance;
    }
    const double inv = 1.0 / s.resolution;
    double u = (x - s.origin.x()) * inv - 0.5;
    double v = (y - s.origin.y()) * inv - 0.5;
    bool inside_x = true, inside_y = true;
    if (u < 0.0) { u = 0.0; inside_x = false; }
    if (v < 0.0) { v = 0.0; inside_y = false; }
    if (u > s.nx - 1) { u = s.nx - 1; inside_x = false; }
    if (v > s.ny - 1) { v = s.ny - 1; inside_y = false; }
    int i0 = std::min(int(u), s.nx - 2);
    int j0 = std::min(int(v), s.ny - 2);
    const double tx = u - i0;
    const double ty = v - j0;
    const float* row0 = &values_[std::size_t(j0) * s.nx];
    const float* row1 = row0 + s.nx;
    const double d00 = row0[i0], d10 = row0[i0 + 1], d01 = row1[i0], d11 = row1[i0 + 1];
    const double a = d00 + tx * (d10 - d00);
    const double b = d01 + tx * (d11 - d01);
    if (grad) {
      (*grad)(0) = inside_x ? ((1.0 - ty) * (d10 - d00) + ty * (d11 - d01)) * inv : 0.0;
      (*grad)(1) = inside_y ? (b - a) * inv : 0.0;
    }
    return a + ty * (b - a);
  }
  /// Slice value of cell (ix, iy) [m] (max_distance outside the slice).
  double cellDistance(int ix, int iy) const {
    if (!geometry_.contains(ix, iy)) return params_.max_distance;
    return values_[std::size_t(iy) * geometry_.nx + ix];
  }
  const SliceGeometry& geometry() const { return geometry_; }
  Eigen::Vector2d boxCenter() const { return box_center_; }
  int64_t incrementalUpdates() const { return incremental_; }
  int64_t rebuilds() const { return rebuilds_; }
  /// The slice recomputed in full from the distance transform, compared value for value with
  /// the incrementally kept one: the number of differing cells (0 before the first update).
  std::size_t mismatches();

 private:
  /// Brings the projection up to date with the 3-D cells changed since the last call.
  void project();
  void rebuild(const Eigen::Vector2d& centre);
  /// The slice's value of cell (ix, iy) from the distance transform (occupied: 0 for now, see
  /// computeInterior).
  void sliceCell(int ix, int iy, float half, float cap);
  void computeSlice(bool full);
  void interiorNear(int x0, int y0, int x1, int y1);
  void computeInterior();

  MapParams params_;
  LeafCache& leaves_;
  /// The projection: a leaf is occupied when any leaf of the height band above it is. The
  /// distance transform runs on this single layer, so its cost does not grow with the band's
  /// height and a 2-D query is one lookup.
  octomap::OcTree flat_;
  std::unique_ptr<DynamicEDTOctomap> edt_;
  octomap::OcTreeKey key_min_, key_max_;
  Eigen::Vector2d box_center_ = Eigen::Vector2d::Zero();
  SliceGeometry geometry_;
  std::vector<float> values_;  // signed distance per slice cell, row-major (iy * nx + ix)
  std::vector<uint8_t> occupied_;
  std::vector<float> scratch_f_, scratch_d_, scratch_z_, scratch_col_;
  std::vector<int> scratch_v_;
  std::vector<ColumnKey> dirty_columns_;
  /// Projection cells whose occupancy changed since the slice was last computed.
  std::vector<ColumnKey> flat_changed_;
  std::vector<uint8_t> dirty_;  // per slice cell: to be recomputed (incremental computeSlice)
  /// Offsets (dx, dy) within the interior search radius, by increasing dx^2 + dy^2.
  struct RingOffset {
    int dx, dy, d2;
  };
  std::vector<RingOffset> ring_;
  int ring_radius_ = -1;
  int64_t incremental_ = 0;
  int64_t rebuilds_ = 0;
};

}  // namespace ucon::planner
