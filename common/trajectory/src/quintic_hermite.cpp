#include "ucon/trajectory/quintic_hermite.hpp"

#include <cmath>

namespace ucon {
namespace trajectory {

std::array<double, 6> quinticHermiteCoefficients(double p0, double v0, double a0, double p1,
                                                 double v1, double a1, double T) {
  // With c0..c2 fixed by the start state, the remaining residuals at t = T are
  // dp = p1 - (p0 + v0 T + a0 T^2/2), dv = v1 - (v0 + a0 T), da = a1 - a0, and the 3x3
  // system for c3..c5 has the closed-form solution below.
  const double dp = p1 - (p0 + v0 * T + 0.5 * a0 * T * T);
  const double dv = v1 - (v0 + a0 * T);
  const double da = a1 - a0;
  const double T2 = T * T, T3 = T2 * T;
  return {p0,
          v0,
          0.5 * a0,
          (10.0 * dp - 4.0 * dv * T + 0.5 * da * T2) / T3,
          (-15.0 * dp + 7.0 * dv * T - da * T2) / (T3 * T),
          (6.0 * dp - 3.0 * dv * T + 0.5 * da * T2) / (T3 * T2)};
}

TrajectoryStatus buildQuinticHermite(int64_t start_utime, const std::vector<KnotState>& knots,
                                     int dim, PiecewisePolynomial* out) {
  if (knots.size() < 2) return TrajectoryStatus::kNoPieces;
  if (dim < 1 || dim > 3) return TrajectoryStatus::kBadDimension;
  const std::size_t n = knots.size() - 1;
  std::vector<double> durations(n);
  std::vector<double> coeffs(n * static_cast<std::size_t>(dim) * 6);
  for (std::size_t k = 0; k < n; ++k) {
    const KnotState& a = knots[k];
    const KnotState& b = knots[k + 1];
    const double T = b.t - a.t;
    if (!std::isfinite(T) || !(T >= PiecewisePolynomial::kMinPieceDuration)) {
      return TrajectoryStatus::kBadDuration;
    }
    durations[k] = T;
    for (int d = 0; d < dim; ++d) {
      const auto c = quinticHermiteCoefficients(a.position[d], a.velocity[d], a.acceleration[d],
                                                b.position[d], b.velocity[d], b.acceleration[d], T);
      for (std::size_t j = 0; j < 6; ++j) {
        coeffs[(k * static_cast<std::size_t>(dim) + static_cast<std::size_t>(d)) * 6 + j] = c[j];
      }
    }
  }
  return PiecewisePolynomial::create(start_utime, dim, 6, std::move(durations), std::move(coeffs), out);
}

}  // namespace trajectory
}  // namespace ucon
