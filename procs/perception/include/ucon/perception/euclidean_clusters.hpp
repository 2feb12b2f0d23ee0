#pragma once
/// @file euclidean_clusters.hpp
/// Euclidean clustering on a voxel grid: the connected components of the graph "closer than
/// the tolerance", exactly the groups of PCL's EuclideanClusterExtraction (kept as the
/// reference in PointIndex::clusters), at a fraction of its time on LiDAR frames.
///
/// The grid's cells have an edge of tolerance / sqrt(3), so every two points of one cell are
/// within the tolerance: a cell is connected by construction, and only pairs of nearby
/// cells not yet connected need a point-to-point test, which stops at the first close pair.
/// Cells are kept as a list sorted by (column, z); a neighbour column is found through a
/// small 2-D table of where each column's cells start.

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace ucon {
namespace perception {

class EuclideanClusterer {
 public:
  /// Groups of indices into `points` whose members are chained by distances < `tolerance`
  /// [m] (squared distances compared in float, as PCL's KD-tree search does); groups with a
  /// size outside [min_points, max_points] are dropped. Each group is sorted; groups are
  /// ordered by their first index. Non-finite points belong to no group; a tolerance that is
  /// not > 0 gives no groups. Scratch buffers are kept between calls (not thread-safe).
  /// @throws std::invalid_argument when the points span more than 1e6 cells per axis (a
  ///         programming error: frames are cropped to the sensor's range long before)
  std::vector<std::vector<int>> cluster(const std::vector<Eigen::Vector3f>& points, double tolerance,
                                        int min_points, int max_points);

 private:
  int findRoot(int c);
  void sortByKey();  // sorted_ by key, ties in index order (stable radix sort)
  std::vector<std::pair<int64_t, int>> radix_tmp_;
  std::vector<std::pair<int64_t, int>> sorted_;  // (cell key, point index) of finite points, sorted
  struct ColumnOffset {
    int64_t d;   // column key difference (dx * ny + dy)
    int dz_max;  // cells of that column within |dz| <= dz_max can hold a close point
  };
  std::vector<ColumnOffset> col_offsets_;  // neighbour columns to test, each column pair once
  std::vector<int> cell_begin_;      // per occupied cell: its range in sorted_ (one extra entry at the end)
  std::vector<int64_t> cell_key_;    // per occupied cell: its key (sorted)
  std::vector<int64_t> cell_col_;    // per occupied cell: its column key (x * ny + y)
  std::vector<int> cell_z_;          // per occupied cell: its z cell
  std::vector<int> parent_;          // union-find over occupied cells
  std::vector<int> col_begin_;       // dense column key -> its first occupied cell (-1: none); reset after use
  std::vector<int> cell_of_point_;   // per point: its occupied cell (-1: not finite)
  std::vector<int> group_of_root_;   // per union-find root: its group (-1: none yet)
};

}  // namespace perception
}  // namespace ucon
