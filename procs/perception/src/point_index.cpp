// All PCL use of the perception node lives in this file (PCL headers compile slowly). The node
// clusters with EuclideanClusterer (same groups, faster) and re-associates with
// ProximityIndex::nearestWithin (same nearest points, no tree to build per frame);
// PointIndex::clusters and PointIndex::nearest stay as the references they are tested against.
#include "ucon/perception/point_index.hpp"

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/search.h>
#include <pcl/segmentation/extract_clusters.h>

#include <nanoflann.hpp>

#include <algorithm>

namespace ucon {
namespace perception {

namespace {
pcl::PointCloud<pcl::PointXYZ>::Ptr toPcl(const Points& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->points.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud->points[i].x = points[i].x();
    cloud->points[i].y = points[i].y();
    cloud->points[i].z = points[i].z();
  }
  cloud->width = static_cast<uint32_t>(points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

/// nanoflann's dataset adaptor over a PCL cloud.
struct CloudAdaptor {
  const pcl::PointCloud<pcl::PointXYZ>* cloud = nullptr;
  std::size_t kdtree_get_point_count() const { return cloud ? cloud->size() : 0; }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*cloud)[i].data[dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>, CloudAdaptor, 3>;

/// PCL's search interface over a nanoflann KD-tree, so that PCL's Euclidean cluster
/// extraction runs on it: the same neighbours as PCL's FLANN tree (points strictly inside
/// the radius, unsorted), with one reused result buffer instead of allocations per query.
class NanoflannSearch : public pcl::search::Search<pcl::PointXYZ> {
 public:
  NanoflannSearch() : pcl::search::Search<pcl::PointXYZ>("NanoflannSearch", false) {}

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override {
    input_ = cloud;
    indices_ = indices;  // the clustering below never passes any
    adaptor_.cloud = cloud.get();
    tree_ = std::make_unique<NanoTree>(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  }

  int nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    k_indices.clear();
    k_sqr_distances.clear();
    if (!tree_ || k <= 0 || input_->empty()) return 0;
    const std::size_t n = std::min<std::size_t>(std::size_t(k), input_->size());
    knn_idx_.resize(n);
    k_sqr_distances.resize(n);
    const std::size_t found = tree_->knnSearch(point.data, n, knn_idx_.data(), k_sqr_distances.data());
    k_sqr_distances.resize(found);
    for (std::size_t i = 0; i < found; ++i) k_indices.push_back(static_cast<pcl::index_t>(knn_idx_[i]));
    return static_cast<int>(found);
  }

  /// The nearest point without PCL's output vectors: index (-1 if empty) and squared distance.
  int nearestOne(const float* q, float* dist2) const {
    if (!tree_ || input_->empty()) return -1;
    uint32_t idx = 0;
    float d2 = 0.0f;
    if (tree_->knnSearch(q, 1, &idx, &d2) < 1) return -1;
    if (dist2) *dist2 = d2;
    return static_cast<int>(idx);
  }

  int radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override {
    k_indices.clear();
    k_sqr_distances.clear();
    if (!tree_ || input_->empty()) return 0;
    const auto r2 = static_cast<float>(radius * radius);
    matches_.clear();
    nanoflann::RadiusResultSet<float, uint32_t> result(r2, matches_);
    tree_->findNeighbors(result, point.data, nanoflann::SearchParams());
    std::size_t n = matches_.size();
    if (max_nn > 0 && n > max_nn) n = max_nn;
    for (std::size_t i = 0; i < n; ++i) {
      k_indices.push_back(static_cast<pcl::index_t>(matches_[i].first));
      k_sqr_distances.push_back(matches_[i].second);
    }
    return static_cast<int>(n);
  }

 private:
  CloudAdaptor adaptor_;
  std::unique_ptr<NanoTree> tree_;
  mutable std::vector<std::pair<uint32_t, float>> matches_;
  mutable std::vector<uint32_t> knn_idx_;
};
}  // namespace

struct PointIndex::Impl {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud;
  std::shared_ptr<NanoflannSearch> tree;
};

PointIndex::PointIndex() : impl_(std::make_unique<Impl>()) {}
PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

void PointIndex::build(const Points& points) {
  impl_->cloud = toPcl(points);
  if (points.empty()) {
    impl_->tree.reset();
    return;
  }
  impl_->tree = std::make_shared<NanoflannSearch>();
  impl_->tree->setInputCloud(impl_->cloud);
}

int PointIndex::size() const { return impl_->cloud ? static_cast<int>(impl_->cloud->size()) : 0; }

int PointIndex::nearest(const Eigen::Vector3f& q, float* dist2) const {
  if (!impl_->tree || !q.allFinite()) return -1;
  return impl_->tree->nearestOne(q.data(), dist2);  // no allocation per query
}

std::vector<std::vector<int>> PointIndex::clusters(double tolerance, int min_points,
                                                   int max_points) const {
  std::vector<std::vector<int>> out;
  if (!impl_->tree || impl_->cloud->empty()) return out;
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(tolerance);
  ec.setMinClusterSize(min_points);
  ec.setMaxClusterSize(max_points);
  ec.setSearchMethod(impl_->tree);
  ec.setInputCloud(impl_->cloud);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);
  out.reserve(found.size());
  for (const auto& c : found) {
    std::vector<int> v(c.indices.begin(), c.indices.end());
    std::sort(v.begin(), v.end());
    out.push_back(std::move(v));
  }
  // Deterministic, size-independent order: by first (lowest) point index.
  std::sort(out.begin(), out.end(),
            [](const std::vector<int>& a, const std::vector<int>& b) { return a.front() < b.front(); });
  return out;
}

Points voxelDownsample(const Points& points, double voxel) {
  if (points.empty()) return {};
  auto cloud = toPcl(points);
  pcl::PointCloud<pcl::PointXYZ> filtered;
  pcl::VoxelGrid<pcl::PointXYZ> vg;
  vg.setInputCloud(cloud);
  const float leaf = static_cast<float>(voxel);
  vg.setLeafSize(leaf, leaf, leaf);
  vg.filter(filtered);
  Points out;
  out.reserve(filtered.size());
  for (const auto& p : filtered.points) out.emplace_back(p.x, p.y, p.z);
  return out;
}

}  // namespace perception
}  // namespace ucon
