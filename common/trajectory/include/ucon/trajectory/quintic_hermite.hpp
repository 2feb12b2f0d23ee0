#pragma once
/// @file quintic_hermite.hpp
/// Quintic Hermite interpolation: the unique quintic per piece that matches position,
/// velocity and acceleration at both knots. Builds trajectories for tests, simulations and
/// fallbacks (a C2 curve through sampled states of an analytic path), not an optimiser.

#include <Eigen/Core>

#include <array>
#include <vector>

#include "ucon/trajectory/piecewise_polynomial.hpp"

namespace ucon {
namespace trajectory {

/// State at one knot.
struct KnotState {
  double t = 0.0;                                          ///< knot time since start [s]
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< [m/s]
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< [m/s^2]
};

/// Coefficients c0..c5 (ascending powers) of the quintic on [0, T] with p(0)=p0, p'(0)=v0,
/// p''(0)=a0, p(T)=p1, p'(T)=v1, p''(T)=a1. T must be > 0.
std::array<double, 6> quinticHermiteCoefficients(double p0, double v0, double a0, double p1,
                                                 double v1, double a1, double T);

/// Builds a quintic piecewise polynomial (order1 = 6) through the knots (times strictly
/// increasing, at least two knots), using the first `dim` axes. Returns the status of the
/// result (kNoPieces for fewer than two knots, kBadDuration for non-increasing times).
TrajectoryStatus buildQuinticHermite(int64_t start_utime, const std::vector<KnotState>& knots,
                                     int dim, PiecewisePolynomial* out);

}  // namespace trajectory
}  // namespace ucon
