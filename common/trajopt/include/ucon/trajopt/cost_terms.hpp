#pragma once
/// @file cost_terms.hpp
/// The penalty terms of the sector-MINCO objective evaluated at one sample, each with its value
/// and analytic partial derivatives with respect to the sample's position p, velocity v,
/// acceleration a and plan-relative time t: static clearance (constraint 13c), the velocity and
/// acceleration limits (13d) and the taper of the dynamic cost at the horizon. The dynamic
/// cost J_d itself is in uncertainty_sector.hpp. The objective integrates them over each piece
/// with the paper's trapezoid weights (eq. 14).

#include <Eigen/Core>

#include "ucon/trajopt/distance_field.hpp"
#include "ucon/trajopt/sector_minco.hpp"
#include "ucon/trajopt/uncertainty_sector.hpp"

namespace ucon::trajopt {

/// Static clearance (constraint Ξ(p) >= s): weight * max(0, s - Ξ(p))^3 (C^2 at the boundary).
/// Adds dC/dp to *grad_p.
double staticClearanceCost(const DistanceField2D& field, const Eigen::Vector2d& p, double safe_distance,
                           double weight, Eigen::Vector2d* grad_p);

/// Limit penalty for ||x|| <= limit (velocity or acceleration): weight * max(0, ||x||^2 - limit^2)^3.
/// Adds dC/dx to *grad_x.
double limitCost(const Eigen::Vector2d& x, double limit, double weight, Eigen::Vector2d* grad_x);

/// Smooth taper of the dynamic cost near the horizon: 1 until horizon - 0.5 s, smoothstep
/// to 0 at the horizon. Writes dw/dt to *dw.
double horizonWeight(double t, double horizon, double* dw);

}  // namespace ucon::trajopt
