#include "ucon/trajopt/cost_terms.hpp"

#include <algorithm>
#include <cmath>

namespace ucon::trajopt {

namespace {

constexpr double kHorizonRamp = 0.5; // [s]

}  // namespace

double staticClearanceCost(const DistanceField2D& field, const Eigen::Vector2d& p, double safe_distance,
                           double weight, Eigen::Vector2d* grad_p) {
  Eigen::Vector2d g;
  const double xi = field.distance(p.x(), p.y(), &g);
  const double viol = safe_distance - xi;
  if (!(viol > 0.0)) return 0.0;
  *grad_p -= 3.0 * weight * viol * viol * g;
  return weight * viol * viol * viol;
}

double limitCost(const Eigen::Vector2d& x, double limit, double weight, Eigen::Vector2d* grad_x) {
  const double viol = x.squaredNorm() - limit * limit;
  if (!(viol > 0.0)) return 0.0;
  *grad_x += 6.0 * weight * viol * viol * x;
  return weight * viol * viol * viol;
}

double horizonWeight(double t, double horizon, double* dw) {
  const double t0 = horizon - kHorizonRamp;
  *dw = 0.0;
  if (t <= t0) return 1.0;
  if (t >= horizon) return 0.0;
  const double u = (t - t0) / kHorizonRamp;
  *dw = -(6.0 * u - 6.0 * u * u) / kHorizonRamp;
  return 1.0 - u * u * (3.0 - 2.0 * u);
}

}  // namespace ucon::trajopt
