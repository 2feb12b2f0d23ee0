#pragma once
/// @file esdf_map.hpp
/// The planner's static map: an OctoMap OcTree fed by ray insertion (all heights), its
/// projection onto one layer (a cell is occupied when any cell of the robot's height band above
/// it is), a DynamicEDT3D distance transform of that layer over a box around the robot (updated
/// incrementally from the octree's change detection; rebuilt when the robot leaves the box's
/// centre region), and a cached 2-D signed distance slice with bilinear interpolation for the
/// optimiser. Projecting first keeps the transform's cost independent of the band's height;
/// the distance of a point to the band's obstacles is the 2-D distance to that projection.
///
/// OctoMap and DynamicEDT3D stay inside src/ (pimpl): src/leaf_cache.hpp (the 3-D tree and its
/// leaf cache), src/ray_insertion.hpp (frames into the tree) and src/distance_slice.hpp (the
/// projection, the distance transform and the slice).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ucon {
class ConfigReader;
struct static_points_t;
}  // namespace ucon

namespace ucon::planner {

/// Map parameters (YAML section `map`).
struct MapParams {
  double resolution = 0.1;        ///< octree leaf size [m], 0.02..1
  double max_range = 12.0;        ///< rays are cut at this range; beyond it only free space [m], > 0
  double band_z_min = 0.1;        ///< lowest height the robot occupies [m]
  double band_z_max = 0.6;        ///< highest height the robot occupies [m], > band_z_min
  double box_half_size = 12.0;    ///< ESDF box half extent in x and y around the robot [m], 1..50
  double recenter_distance = 5.0; ///< rebuild the box when the robot is this far from its centre [m]
  double max_distance = 1.0;      ///< distances are clamped at this value [m], > resolution
  double prob_hit = 0.7;          ///< OctoMap hit probability, 0.5..1
  double prob_miss = 0.4;         ///< OctoMap miss probability, 0..0.5
  /// Insert only points within one leaf of the height band: higher or lower returns cannot
  /// change the band's occupancy, and the rays to the in-band returns clear its free space.
  /// Cuts the ray-insertion work to the share of returns in the band. false = every point.
  bool band_only = true;
  /// Threads of a band-only insertion, 1 or 2: with 2, a helper thread traces the second
  /// half of the rays while the caller's thread traces and applies the first; the map is the
  /// same either way (the updates are applied in the same order).
  int insert_threads = 2;

  void read(ConfigReader& r);
  /// Empty when valid, otherwise "<key>: <why>".
  std::string validate() const;
};

/// Outcome of inserting one static_points_t.
enum class InsertStatus { kOk, kInvalidMessage, kBadOrigin, kEmpty };
const char* toString(InsertStatus s);

/// Geometry of the cached 2-D slice: cell (ix, iy) has its centre at
/// origin + (ix + 0.5, iy + 0.5) * resolution.
struct SliceGeometry {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< lower-left corner of cell (0,0) [m]
  double resolution = 0.1;                           ///< cell size [m]
  int nx = 0;
  int ny = 0;
  Eigen::Vector2d cellCenter(int ix, int iy) const {
    return origin + Eigen::Vector2d(ix + 0.5, iy + 0.5) * resolution;
  }
  bool contains(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < nx && iy < ny; }
};

/// Static occupancy + ESDF. Not copyable (owns the octree and the distance transform).
class EsdfMap {
 public:
  explicit EsdfMap(const MapParams& params);
  ~EsdfMap();
  EsdfMap(const EsdfMap&) = delete;
  EsdfMap& operator=(const EsdfMap&) = delete;

  /// Ray-inserts a frame of static points from its sensor origin, clipped at
  /// min(msg.max_range, params.max_range): cells along each ray become freer, end points
  /// more occupied. Non-finite points are skipped and counted in `*skipped`.
  InsertStatus insert(const static_points_t& msg, int64_t* skipped = nullptr);
  /// Same for raw points [m], world frame.
  InsertStatus insert(const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3f>& points,
                      double max_range, int64_t* skipped = nullptr);

  /// Sets the leaf containing `p` to fully occupied or fully free (clamping log-odds), as a
  /// map built from known geometry would (benchmark worlds, tests). Non-finite p is ignored.
  void setCell(const Eigen::Vector3d& p, bool occupied);
  /// Marks every leaf whose centre lies in the vertical cylinder (x, y, radius) within the
  /// height band as occupied (or, with occupied false, as free). With `keep_column`, the
  /// columns whose centre (x, y) [m] it returns true for are left as they are.
  void addCylinder(double x, double y, double radius, bool occupied = true,
                   const std::function<bool(double, double)>& keep_column = nullptr);
  /// Marks every leaf whose centre lies in the axis-aligned box [x0,x1]x[y0,y1] within the
  /// height band as occupied.
  void addBox(double x0, double y0, double x1, double y1);
  /// True if the leaf containing `p` exists and is occupied.
  bool isOccupied(const Eigen::Vector3d& p) const;

  /// Brings the distance transform up to date around `robot_xy` [m]: incremental update when
  /// the box still covers the robot (|robot - centre|_inf < recenter_distance), a fresh box
  /// centred on the robot otherwise (or when `force_rebuild`). Recomputes the 2-D slice.
  /// Returns true when the box was rebuilt.
  bool update(const Eigen::Vector2d& robot_xy, bool force_rebuild = false);

  /// True once update() has run at least once.
  bool ready() const;

  /// Interpolated signed distance [m] at (x, y) to the nearest occupied cell of the height
  /// band (negative inside obstacles), clamped at max_distance; bilinear between cell centres,
  /// so `grad` (d/dx, d/dy, unitless) is exact for the interpolant. Outside the slice: the
  /// value at the nearest border cell with zero gradient. Before the first update():
  /// max_distance with zero gradient. ~20 ns per query.
  double distance(double x, double y, Eigen::Vector2d* grad) const;
  /// Slice value of cell (ix, iy) (signed distance of its centre) [m].
  double cellDistance(int ix, int iy) const;
  /// Slice geometry of the last update.
  const SliceGeometry& slice() const;
  /// Centre of the ESDF box [m].
  Eigen::Vector2d boxCenter() const;
  /// Number of incremental updates and rebuilds so far.
  int64_t incrementalUpdates() const;
  int64_t rebuilds() const;
  /// Consistency check for tests: the slice recomputed in full from the distance transform,
  /// compared exactly with the one kept up to date incrementally; the number of differing
  /// cells (0 when the incremental slice update is right). Changes nothing.
  std::size_t sliceMismatches() const;
  /// Occupied leaves in the tree (all heights).
  std::size_t occupiedLeafCount() const;
  /// Nodes of the 3-D tree, inner ones included (about 30 bytes of memory each).
  std::size_t treeNodeCount() const;
  /// Prunes the 3-D tree now (subtrees whose leaves all agree become one node); the map's
  /// answers do not change. Insertion prunes by itself whenever the tree has grown by half.
  void pruneTree();
  const MapParams& params() const;
  /// CPU seconds the insertion's helper thread has used (0 with insert_threads = 1).
  double helperCpuSeconds() const;
  /// Test hook: whether the insertion's ray traversal visits exactly the cells OctoMap's
  /// computeRayKeys lists for the ray origin -> end [m], in the same order; `cells` gets how
  /// many that is.
  bool rayKeysMatchOctomap(const Eigen::Vector3f& origin, const Eigen::Vector3f& end,
                           std::size_t* cells = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ucon::planner
