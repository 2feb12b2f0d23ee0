// The planner's static map behind a small facade: the 3-D tree and its leaf cache
// (leaf_cache.hpp), ray insertion (ray_insertion.hpp) and the 2-D distance slice
// (distance_slice.hpp).
#include "ucon/planner/esdf_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "distance_slice.hpp"
#include "leaf_cache.hpp"
#include "ray_insertion.hpp"
#include "ucon/config.hpp"
#include "ucon/static_points_t.hpp"

namespace ucon::planner {

void MapParams::read(ConfigReader& r) {
  r.read("resolution", resolution, 0.02, 1.0);
  r.read("max_range", max_range, 0.5, 100.0);
  r.read("band_z_min", band_z_min, -10.0, 10.0);
  r.read("band_z_max", band_z_max, -10.0, 10.0);
  r.read("box_half_size", box_half_size, 1.0, 50.0);
  r.read("recenter_distance", recenter_distance, 0.0, 50.0);
  r.read("max_distance", max_distance, 0.05, 20.0);
  r.read("prob_hit", prob_hit, 0.5, 1.0);
  r.read("prob_miss", prob_miss, 0.0, 0.5);
  r.read("band_only", band_only);
  r.read("insert_threads", insert_threads, 1, 2);
  const std::string why = validate();
  if (!why.empty()) r.fail(why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
}

std::string MapParams::validate() const {
  if (!(resolution > 0.0)) return "resolution: must be > 0";
  if (!(band_z_max > band_z_min)) return "band_z_max: must be greater than band_z_min";
  if (!(max_distance > resolution)) return "max_distance: must exceed resolution";
  if (!(recenter_distance < box_half_size)) return "recenter_distance: must be below box_half_size";
  if (!(max_range > 0.0)) return "max_range: must be > 0";
  if (insert_threads < 1 || insert_threads > 2) return "insert_threads: must be 1 or 2";
  return {};
}

const char* toString(InsertStatus s) {
  switch (s) {
    case InsertStatus::kOk: return "ok";
    case InsertStatus::kInvalidMessage: return "invalid message (valid=false, utime<=0 or bad sizes)";
    case InsertStatus::kBadOrigin: return "sensor origin not finite";
    case InsertStatus::kEmpty: return "no finite points";
  }
  return "unknown";
}

struct EsdfMap::Impl {
  MapParams params;
  LeafCache leaves;       // the 3-D map, all heights
  RayInsertion rays;      // how frames get into it
  DistanceSlice slice;    // its band's 2-D signed distance
  explicit Impl(const MapParams& p) : params(p), leaves(p), rays(p), slice(p, leaves) {}
};

EsdfMap::EsdfMap(const MapParams& params) : impl_(std::make_unique<Impl>(params)) {}
EsdfMap::~EsdfMap() = default;

InsertStatus EsdfMap::insert(const static_points_t& msg, int64_t* skipped) {
  if (!msg.valid || msg.utime <= 0 || msg.num_points < 0 ||
      msg.x.size() != std::size_t(msg.num_points) || msg.y.size() != std::size_t(msg.num_points) ||
      msg.z.size() != std::size_t(msg.num_points)) {
    return InsertStatus::kInvalidMessage;
  }
  std::vector<Eigen::Vector3f> pts(std::size_t(msg.num_points));
  for (int i = 0; i < msg.num_points; ++i) pts[i] = Eigen::Vector3f(msg.x[i], msg.y[i], msg.z[i]);
  double range = impl_->params.max_range;
  if (std::isfinite(msg.max_range) && msg.max_range > 0.0f) range = std::min(range, double(msg.max_range));
  return insert(Eigen::Vector3d(msg.origin_x, msg.origin_y, msg.origin_z), pts, range, skipped);
}

InsertStatus EsdfMap::insert(const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3f>& points,
                             double max_range, int64_t* skipped) {
  if (!origin.allFinite()) return InsertStatus::kBadOrigin;
  Impl& m = *impl_;
  const double range = (std::isfinite(max_range) && max_range > 0.0) ? max_range : m.params.max_range;
  return m.rays.insert(m.leaves, origin, points, range, skipped);
}

void EsdfMap::setCell(const Eigen::Vector3d& p, bool occupied) {
  if (!p.allFinite()) return;
  LeafCache& leaves = impl_->leaves;
  const octomap::OcTree& t = leaves.tree();
  octomap::OcTreeKey key;
  if (!t.coordToKeyChecked(octomap::point3d(float(p.x()), float(p.y()), float(p.z())), key)) return;
  const float v = occupied ? t.getClampingThresMaxLog() : t.getClampingThresMinLog();
  // Setting a leaf to the value it already holds changes nothing (see LeafCache).
  float now = 0.0f;
  const bool known = leaves.leafValue(key, &now);
  if (known && now == v) return;
  leaves.writeLeaf(key, known, now, v);
  leaves.pruneIfGrown();
}

void EsdfMap::addCylinder(double x, double y, double radius, bool occupied,
                          const std::function<bool(double, double)>& keep_column) {
  const double res = impl_->leaves.tree().getResolution();
  const double z0 = impl_->params.band_z_min;
  const double z1 = impl_->params.band_z_max;
  for (double yy = std::floor((y - radius) / res) * res + 0.5 * res; yy <= y + radius; yy += res) {
    for (double xx = std::floor((x - radius) / res) * res + 0.5 * res; xx <= x + radius; xx += res) {
      if ((xx - x) * (xx - x) + (yy - y) * (yy - y) > radius * radius) continue;
      if (keep_column && keep_column(xx, yy)) continue;
      for (double zz = std::floor(z0 / res) * res + 0.5 * res; zz <= z1 + 0.5 * res; zz += res) {
        setCell(Eigen::Vector3d(xx, yy, zz), occupied);
      }
    }
  }
}

void EsdfMap::addBox(double x0, double y0, double x1, double y1) {
  const double res = impl_->leaves.tree().getResolution();
  const double z0 = impl_->params.band_z_min;
  const double z1 = impl_->params.band_z_max;
  for (double yy = std::floor(y0 / res) * res + 0.5 * res; yy <= y1; yy += res) {
    for (double xx = std::floor(x0 / res) * res + 0.5 * res; xx <= x1; xx += res) {
      if (xx < x0 || yy < y0) continue;
      for (double zz = std::floor(z0 / res) * res + 0.5 * res; zz <= z1 + 0.5 * res; zz += res) {
        setCell(Eigen::Vector3d(xx, yy, zz), true);
      }
    }
  }
}

bool EsdfMap::isOccupied(const Eigen::Vector3d& p) const {
  const octomap::OcTree& t = impl_->leaves.tree();
  auto* n = t.search(p.x(), p.y(), p.z());
  return n && t.isNodeOccupied(n);
}

bool EsdfMap::update(const Eigen::Vector2d& robot_xy, bool force_rebuild) {
  return impl_->slice.update(robot_xy, force_rebuild);
}

bool EsdfMap::ready() const { return impl_->slice.ready(); }
double EsdfMap::helperCpuSeconds() const { return impl_->rays.helperCpuSeconds(); }

double EsdfMap::distance(double x, double y, Eigen::Vector2d* grad) const {
  return impl_->slice.distance(x, y, grad);
}

double EsdfMap::cellDistance(int ix, int iy) const { return impl_->slice.cellDistance(ix, iy); }

const SliceGeometry& EsdfMap::slice() const { return impl_->slice.geometry(); }
Eigen::Vector2d EsdfMap::boxCenter() const { return impl_->slice.boxCenter(); }
int64_t EsdfMap::incrementalUpdates() const { return impl_->slice.incrementalUpdates(); }
int64_t EsdfMap::rebuilds() const { return impl_->slice.rebuilds(); }
std::size_t EsdfMap::sliceMismatches() const { return impl_->slice.mismatches(); }
const MapParams& EsdfMap::params() const { return impl_->params; }

std::size_t EsdfMap::treeNodeCount() const { return impl_->leaves.tree().size(); }

void EsdfMap::pruneTree() { impl_->leaves.prune(); }

std::size_t EsdfMap::occupiedLeafCount() const {
  const octomap::OcTree& t = impl_->leaves.tree();
  std::size_t n = 0;
  for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it) {
    if (t.isNodeOccupied(*it)) n += std::size_t(1) << (3 * (t.getTreeDepth() - it.getDepth()));
  }
  return n;
}

bool EsdfMap::rayKeysMatchOctomap(const Eigen::Vector3f& origin, const Eigen::Vector3f& end,
                                  std::size_t* cells) const {
  const octomap::OcTree& t = impl_->leaves.tree();
  const octomap::point3d o(origin.x(), origin.y(), origin.z()), e(end.x(), end.y(), end.z());
  octomap::KeyRay ray;
  const bool ok_octomap = t.computeRayKeys(o, e, ray);
  std::vector<octomap::OcTreeKey> mine;
  const bool ok_mine = traceRayKeys(t, o, e, [&](const octomap::OcTreeKey& k) { mine.push_back(k); });
  if (cells) *cells = mine.size();
  if (ok_octomap != ok_mine) return false;
  if (!ok_octomap) return true;
  return std::equal(ray.begin(), ray.end(), mine.begin(), mine.end());
}

}  // namespace ucon::planner
