#include "probe.hpp"

#include <algorithm>
#include <cmath>

namespace ucon::bench {

PlayResult playPlan(const trajectory::PiecewisePolynomial& pp, double t0, double horizon, const world::World& w,
                    double robot_radius, double step) {
  PlayResult r;
  if (!pp.valid() || !(horizon > 0.0) || !(step > 0.0)) return r;
  const int n = int(std::ceil(horizon / step - 1e-9));
  const double duration = pp.duration();
  // Only what the robot and a mover can both reach within the horizon is examined.
  const Eigen::Vector2d p0 = pp.sampleRelative(0.0).position.head<2>();
  double reach = 0.0;
  std::vector<Eigen::Vector2d> path(std::size_t(n) + 1);
  for (int k = 0; k <= n; ++k) {
    const double s = std::min(k * step, horizon);
    path[std::size_t(k)] = pp.sampleRelative(std::min(s, duration)).position.head<2>();
    reach = std::max(reach, (path[std::size_t(k)] - p0).norm());
  }
  const auto& sc = w.scenario();
  std::vector<std::size_t> movers;
  for (std::size_t i = 0; i < w.numMovers(); ++i) {
    const world::ObstacleState o = w.moverState(i, t0);
    // Speeds never exceed 1.5 m/s in the bench worlds; 2 m/s leaves room for other scenarios.
    if ((o.position - p0).norm() <= reach + robot_radius + o.radius + 2.0 * horizon + 1.0) movers.push_back(i);
  }
  std::vector<std::size_t> statics;
  for (std::size_t i = 0; i < sc.statics.size(); ++i) {
    if (w.staticFootprintDistance(i, p0) <= reach + robot_radius + 0.1) statics.push_back(i);
  }
  double jerk_sum = 0.0;
  int jerk_n = 0;
  for (int k = 0; k <= n; ++k) {
    const double s = std::min(k * step, horizon);
    const Eigen::Vector2d& p = path[std::size_t(k)];
    if (s <= duration) {
      jerk_sum += pp.sampleRelative(s).jerk.head<2>().norm();
      ++jerk_n;
    }
    if (!r.mover_contact) {
      for (const std::size_t i : movers) {
        const world::ObstacleState o = w.moverState(i, t0 + s);
        if ((p - o.position).norm() < robot_radius + o.radius) {
          r.mover_contact = true;
          r.mover = int(i);
          if (r.contact_s < 0.0) r.contact_s = s;
          break;
        }
      }
    }
    if (!r.static_contact) {
      for (const std::size_t i : statics) {
        if (w.staticFootprintDistance(i, p) < robot_radius) {
          r.static_contact = true;
          if (r.contact_s < 0.0) r.contact_s = s;
          break;
        }
      }
    }
  }
  r.jerk_mean = jerk_n > 0 ? jerk_sum / jerk_n : 0.0;
  return r;
}

}  // namespace ucon::bench
