#pragma once
/// @file probe.hpp
/// The open-loop probe of the planning benchmark (issue 31): a raw plan played against the
/// movers' true motion. The robot's body follows the plan from its start (at rest at its end
/// after it ends) for `horizon` seconds; every check_step the disk of radius robot_radius is
/// tested against every mover's true body and every static footprint.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/world/world.hpp"

namespace ucon::bench {

struct PlayResult {
  bool mover_contact = false;   ///< the body touched a mover within the horizon
  bool static_contact = false;  ///< ... a static obstacle
  int mover = -1;               ///< the first mover touched (index into the world's movers)
  double contact_s = -1.0;      ///< seconds after the plan's start of the first contact of either kind
  double jerk_mean = 0.0;       ///< mean |p'''| over the plan's part within the horizon [m/s^3]
  bool contactFree() const { return !mover_contact && !static_contact; }
};

/// Plays `pp` from its start for `horizon` seconds against `w`'s true motion; the plan's start
/// is at world time `t0` [s]. Samples every `step` seconds.
PlayResult playPlan(const trajectory::PiecewisePolynomial& pp, double t0, double horizon, const world::World& w,
                    double robot_radius, double step = 0.02);

}  // namespace ucon::bench
