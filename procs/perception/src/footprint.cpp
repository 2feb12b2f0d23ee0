#include "ucon/perception/footprint.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace perception {

Eigen::Vector2d viewCorrectedCenter(const Points& points, const std::vector<int>& indices,
                                    const Eigen::Vector2d& sensor_xy, double max_shift) {
  if (indices.empty()) return Eigen::Vector2d::Zero();
  Eigen::Vector2d lo = points[static_cast<std::size_t>(indices[0])].head<2>().cast<double>(), hi = lo;
  for (int i : indices) {
    const Eigen::Vector2d p = points[static_cast<std::size_t>(i)].head<2>().cast<double>();
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector2d box_center = 0.5 * (lo + hi);
  const Eigen::Vector2d view = box_center - sensor_xy;
  const double range = view.norm();
  if (!(max_shift > 0.0) || !(range > 1e-6)) return box_center;
  const Eigen::Vector2d u = view / range;
  const Eigen::Vector2d n(-u.y(), u.x());
  double a_lo = INFINITY, a_hi = -INFINITY, b_lo = INFINITY, b_hi = -INFINITY;
  for (int i : indices) {
    const Eigen::Vector2d p = points[static_cast<std::size_t>(i)].head<2>().cast<double>();
    const double a = u.dot(p), b = n.dot(p);
    a_lo = std::min(a_lo, a);
    a_hi = std::max(a_hi, a);
    b_lo = std::min(b_lo, b);
    b_hi = std::max(b_hi, b);
  }
  const double shift = std::clamp(0.5 * ((b_hi - b_lo) - (a_hi - a_lo)), 0.0, max_shift);
  return u * (0.5 * (a_lo + a_hi) + shift) + n * (0.5 * (b_lo + b_hi));
}

}  // namespace perception
}  // namespace ucon
