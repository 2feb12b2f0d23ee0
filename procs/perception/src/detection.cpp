#include "ucon/perception/detection.hpp"

#include "ucon/perception/footprint.hpp"

namespace ucon {
namespace perception {

Detector::Detector(const SegmentationParams& params) : params_(params) {}

const std::vector<std::vector<int>>& Detector::cluster(const Frame& frame) {
  const SegmentationParams& s = params_;
  groups_ = clusterer_.cluster(frame.points, s.cluster_tolerance, s.min_cluster_points, s.max_cluster_points);
  if (s.far_cluster_tolerance > s.cluster_tolerance) {
    // Far away the scan is sparse: a person's few returns lie farther apart than the near
    // tolerance. The points no cluster took that lie beyond far_cluster_range are clustered
    // again with the far tolerance; near clusters stay as they were.
    const Points& pts = frame.points;
    std::vector<char>& used = far_used_;
    used.assign(pts.size(), 0);
    for (const auto& g : groups_)
      for (int i : g) used[static_cast<std::size_t>(i)] = 1;
    const Eigen::Vector2f o = frame.sensor_origin.head<2>();
    const float r2 = static_cast<float>(s.far_cluster_range * s.far_cluster_range);
    far_points_.clear();
    far_index_.clear();
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (!used[i] && (pts[i].head<2>() - o).squaredNorm() >= r2) {
        far_points_.push_back(pts[i]);
        far_index_.push_back(static_cast<int>(i));
      }
    for (auto& c : clusterer_.cluster(far_points_, s.far_cluster_tolerance, s.min_cluster_points, s.max_cluster_points)) {
      for (int& k : c) k = far_index_[static_cast<std::size_t>(k)];
      groups_.push_back(std::move(c));
    }
  }
  return groups_;
}

Detection Detector::describe(const Frame& frame, const std::vector<int>& g,
                             const std::vector<Eigen::Vector2d>& predicted) const {
  const SegmentationParams& s = params_;
  const Points& pts = frame.points;
  Detection d;
  d.indices = g;
  Eigen::Vector3f lo = pts[g[0]], hi = lo;
  double zsum = 0.0;
  for (int i : g) {
    lo = lo.cwiseMin(pts[i]);
    hi = hi.cwiseMax(pts[i]);
    zsum += pts[i].z();
  }
  d.box.center = viewCorrectedCenter(pts, g, frame.sensor_origin.head<2>().cast<double>(), s.view_center_shift);
  d.box.size = (hi - lo).head<2>().cast<double>();
  d.min_z = lo.z();
  d.max_z = hi.z();
  d.mean_z = zsum / static_cast<double>(g.size());
  d.size_ok = d.box.size.maxCoeff() <= s.max_object_size && (d.max_z - d.min_z) >= s.min_object_height;
  if (d.size_ok) {
    const double support2 = s.track_support_distance * s.track_support_distance;
    for (const auto& p : predicted) {
      if ((p - d.box.center).squaredNorm() <= support2) {
        d.supported = true;
        break;
      }
    }
  }
  return d;
}

std::vector<Detection> Detector::classify(Frame* frame, const MotionTest& motion,
                                          const std::vector<Eigen::Vector2d>& predicted, int* split_parts) {
  const SegmentationParams& s = params_;
  Frame& f = *frame;
  std::vector<Detection> out;
  *split_parts = 0;
  const bool test = motion.hasReference();
  for (const auto& g : groups_) {
    Detection d = describe(f, g, predicted);
    if (d.size_ok && test) {
      d.moving = static_cast<double>(motion.markMoved(f, g, d.box.center, &f.moved, &d.evidence)) >=
                 s.motion_ratio * static_cast<double>(g.size());
    } else if (!d.size_ok && test && d.box.size.maxCoeff() <= s.split_max_size &&
               (d.max_z - d.min_z) >= s.min_object_height) {
      // Too large for one object, small enough to be an object brushing a pillar or a box:
      // its moved points, clustered on their own, are the object (the rest stays structure).
      motion.markMoved(f, g, d.box.center, &f.moved);
      Points moved_pts;
      std::vector<int> moved_idx;
      for (int i : g)
        if (f.moved[i]) {
          moved_pts.push_back(f.points[i]);
          moved_idx.push_back(i);
        }
      if (static_cast<int>(moved_idx.size()) >= s.min_cluster_points) {
        for (const auto& c : clusterer_.cluster(moved_pts, s.cluster_tolerance, s.min_cluster_points, s.max_cluster_points)) {
          std::vector<int> idx;
          for (int k : c) idx.push_back(moved_idx[static_cast<std::size_t>(k)]);
          Detection part = describe(f, idx, predicted);
          if (!part.size_ok) continue;
          part.moving = true;
          ++*split_parts;
          out.push_back(std::move(part));
        }
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace perception
}  // namespace ucon
