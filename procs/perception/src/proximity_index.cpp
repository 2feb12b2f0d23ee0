// nanoflann is included here only (a large header-only template library).
#include "ucon/perception/proximity_index.hpp"

#include <nanoflann.hpp>

#include <cmath>
#include <limits>

namespace ucon {
namespace perception {

namespace {
/// nanoflann's dataset adaptor over the stored points.
struct Cloud {
  std::vector<Eigen::Vector3f> pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return pts[i][static_cast<Eigen::Index>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // let nanoflann compute it
  }
};

/// Result set that accepts the first point inside the ball and ends the search there.
/// nanoflann hands it points with dist < worstDist(), so the bound is the next float above
/// the squared radius (a point exactly on the sphere counts, as in "nearest distance <= r").
class FirstWithin {
 public:
  explicit FirstWithin(float max_dist2) : bound_(std::nextafter(max_dist2, std::numeric_limits<float>::infinity())) {}
  bool full() const { return found_; }
  float worstDist() const { return bound_; }
  bool addPoint(float /*dist*/, std::size_t /*index*/) {
    found_ = true;
    return false;  // stop searching
  }
  bool found() const { return found_; }

 private:
  float bound_;
  bool found_ = false;
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3>;
}  // namespace

struct ProximityIndex::Impl {
  Cloud cloud;
  std::unique_ptr<Tree> tree;
};

ProximityIndex::ProximityIndex() : impl_(std::make_unique<Impl>()) {}
ProximityIndex::~ProximityIndex() = default;
ProximityIndex::ProximityIndex(ProximityIndex&&) noexcept = default;
ProximityIndex& ProximityIndex::operator=(ProximityIndex&&) noexcept = default;

void ProximityIndex::build(const std::vector<Eigen::Vector3f>& points) {
  impl_->tree.reset();
  impl_->cloud.pts.clear();
  impl_->cloud.pts.reserve(points.size());
  for (const auto& p : points)
    if (p.allFinite()) impl_->cloud.pts.push_back(p);
  if (impl_->cloud.pts.empty()) return;
  impl_->tree = std::make_unique<Tree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
}

int ProximityIndex::size() const { return static_cast<int>(impl_->cloud.pts.size()); }

bool ProximityIndex::anyWithin(const Eigen::Vector3f& q, float max_dist2) const {
  if (!impl_->tree || !q.allFinite() || !std::isfinite(max_dist2) || max_dist2 < 0.0f) return false;
  FirstWithin result(max_dist2);
  impl_->tree->findNeighbors(result, q.data(), nanoflann::SearchParams());
  return result.found();
}

}  // namespace perception
}  // namespace ucon
