#include "ucon/perception/measurement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "ucon/perception/footprint.hpp"

namespace ucon {
namespace perception {

Measurer::Measurer(const SegmentationParams& params, const AngularGrid& grid) : params_(params), grid_(grid) {}

Measurement Measurer::measure(const Frame& frame, const std::vector<int>& indices,
                              std::optional<double> track_width) const {
  const Points& pts = frame.points;
  Measurement m;
  if (indices.empty()) return m;
  Eigen::Vector3f lo = pts[indices[0]], hi = lo;
  double zsum = 0.0;
  m.points.reserve(indices.size());
  for (int i : indices) {
    const auto& p = pts[i];
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    zsum += p.z();
    m.points.push_back(p);
  }
  const Eigen::Vector2d sensor = frame.sensor_origin.head<2>().cast<double>();
  m.box.center = viewCorrectedCenter(pts, indices, sensor, params_.view_center_shift);
  m.box.size = (hi - lo).head<2>().cast<double>();
  m.size_z = hi.z() - lo.z();
  // Extent across the line of sight. A view cut on one side by something nearer (a pillar, a
  // person in front) has its centre pulled towards the visible side, and the differenced
  // velocity with it: with the track's width from uncut views, the centre is placed that
  // width from the visible edge instead.
  const Eigen::Vector2d view = m.box.center - sensor;
  if (view.norm() > 1e-6) {
    const Eigen::Vector2d u = view.normalized(), n(-u.y(), u.x());
    double b_lo = INFINITY, b_hi = -INFINITY;
    for (int i : indices) {
      const double b = n.dot(pts[i].head<2>().cast<double>());
      b_lo = std::min(b_lo, b);
      b_hi = std::max(b_hi, b);
    }
    m.width = b_hi - b_lo;
    const double anchor = params_.occlusion_anchor;
    if (track_width && anchor > 0.0) {
      const bool cut_lo = edgeOccluded(frame, indices, n, false), cut_hi = edgeOccluded(frame, indices, n, true);
      m.occluded = cut_lo || cut_hi;
      if (cut_lo != cut_hi && *track_width > 0.0 && m.width < *track_width - anchor) {
        const double b_mid = cut_hi ? b_lo + 0.5 * *track_width : b_hi - 0.5 * *track_width;
        m.box.center += n * (b_mid - 0.5 * (b_lo + b_hi));
        m.cut = true;
      }
    }
  }
  m.center << m.box.center, zsum / static_cast<double>(indices.size());
  return m;
}

bool Measurer::edgeOccluded(const Frame& frame, const std::vector<int>& indices, const Eigen::Vector2d& n,
                            bool hi) const {
  // The outermost points on that side, each looked past by one to three angular bins (turned
  // about the vertical towards that side; the bin's row and the rows above and below, a
  // frame's returns are sparse): a return nearer than the point by occlusion_margin there is
  // an occluder. A pillar a person brushes is not (it stands too close to the person), nor is
  // the ground (at a point's elevation it lies beyond the point).
  constexpr int kEdgePoints = 3, kSteps = 3;
  const Points& pts = frame.points;
  const auto margin = static_cast<float>(params_.occlusion_margin);
  const double sign = hi ? 1.0 : -1.0;
  // The kEdgePoints largest (sign * n.p, index) pairs, largest first, without allocating.
  std::array<std::pair<double, int>, kEdgePoints> edge;
  int k = 0;
  for (int i : indices) {
    const std::pair<double, int> e(sign * n.dot(pts[i].head<2>().cast<double>()), i);
    int at = k;
    while (at > 0 && (e.first > edge[at - 1].first || (e.first == edge[at - 1].first && e.second < edge[at - 1].second))) --at;
    if (at >= kEdgePoints) continue;
    for (int m = std::min(k, kEdgePoints - 1); m > at; --m) edge[m] = edge[m - 1];
    edge[at] = e;
    k = std::min(k + 1, kEdgePoints);
  }
  // +n is the line of sight turned anticlockwise: turning a ray anticlockwise looks past the hi side.
  const double bin = grid_.binRad();
  std::array<float, kSteps> cs, sn;
  for (int step = 1; step <= kSteps; ++step) {
    cs[step - 1] = static_cast<float>(std::cos(sign * bin * step));
    sn[step - 1] = static_cast<float>(std::sin(sign * bin * step));
  }
  const int n_el = grid_.elevationBins();
  for (int e = 0; e < k; ++e) {
    const Eigen::Vector3f ray = pts[edge[e].second] - frame.sensor_origin;
    const float r = ray.norm();
    for (int step = 0; step < kSteps; ++step) {
      const float c = cs[step], s = sn[step];
      const Eigen::Vector3f turned(c * ray.x() - s * ray.y(), s * ray.x() + c * ray.y(), ray.z());
      const int b = grid_.bin(turned), az = b / n_el, el = b % n_el;
      for (int de = -1; de <= 1; ++de) {
        if (el + de < 0 || el + de >= n_el) continue;
        if (frame.nearest_fine[static_cast<std::size_t>(az * n_el + el + de)] < r - margin) return true;
      }
    }
  }
  return false;
}

std::vector<int> restrictToTrack(const Points& points, const std::vector<char>& moved, const Eigen::Vector2d& center,
                                 const Eigen::Vector2d& size, double margin, const std::vector<int>& indices) {
  // A cluster much larger than the track's box is the object merged with something else (a
  // pillar it brushes, another person): measure only the points inside the track's predicted
  // box grown by the margin, if enough of them are there.
  Eigen::Vector2d lo = points[indices[0]].head<2>().cast<double>(), hi = lo;
  for (int i : indices) {
    lo = lo.cwiseMin(points[i].head<2>().cast<double>());
    hi = hi.cwiseMax(points[i].head<2>().cast<double>());
  }
  if (((hi - lo).array() <= (size.array() + margin)).all()) return indices;
  const Eigen::Vector2d half = 0.5 * size + Eigen::Vector2d::Constant(0.5 * margin);
  std::vector<int> inside;
  for (int i : indices) {
    const Eigen::Vector2d d = (points[i].head<2>().cast<double>() - center).cwiseAbs();
    if ((d.array() <= half.array()).all()) inside.push_back(i);
  }
  // Of those, the points that moved (a pillar's do not), when there are enough.
  std::vector<int> moved_inside;
  for (int i : inside)
    if (moved[i]) moved_inside.push_back(i);
  if (moved_inside.size() >= 3) return moved_inside;
  return inside.size() >= 3 ? inside : indices;
}

std::vector<std::vector<int>> splitByNearest(const Points& points, const std::vector<int>& indices,
                                             const std::vector<Eigen::Vector2d>& centers) {
  std::vector<std::vector<int>> parts(centers.size());
  if (centers.empty()) return parts;
  for (int i : indices) {
    const Eigen::Vector2d q = points[static_cast<std::size_t>(i)].head<2>().cast<double>();
    std::size_t best = 0;
    double best_d = (centers[0] - q).squaredNorm();
    for (std::size_t k = 1; k < centers.size(); ++k) {
      const double d = (centers[k] - q).squaredNorm();
      if (d < best_d) best_d = d, best = k;
    }
    parts[best].push_back(i);
  }
  return parts;
}

double movedShare(const std::vector<char>& moved, const std::vector<int>& indices) {
  if (indices.empty()) return 0.0;
  std::size_t n = 0;
  for (int i : indices) n += moved[i] ? 1 : 0;
  return static_cast<double>(n) / static_cast<double>(indices.size());
}

}  // namespace perception
}  // namespace ucon
