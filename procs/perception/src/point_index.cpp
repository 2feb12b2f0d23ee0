// All PCL use of the perception node lives in this file (PCL headers compile slowly).
#include "ucon/perception/point_index.hpp"

#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

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
}  // namespace

struct PointIndex::Impl {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree;  // sorted results off: nearest-only queries
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
  impl_->tree.reset(new pcl::search::KdTree<pcl::PointXYZ>(false));
  impl_->tree->setInputCloud(impl_->cloud);
}

int PointIndex::size() const { return impl_->cloud ? static_cast<int>(impl_->cloud->size()) : 0; }

int PointIndex::nearest(const Eigen::Vector3f& q, float* dist2) const {
  if (!impl_->tree || !q.allFinite()) return -1;
  pcl::PointXYZ p;
  p.x = q.x();
  p.y = q.y();
  p.z = q.z();
  pcl::Indices idx(1);
  std::vector<float> d2(1);
  if (impl_->tree->nearestKSearch(p, 1, idx, d2) < 1) return -1;
  if (dist2) *dist2 = d2[0];
  return idx[0];
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
