#include "ucon/minco/time_map.hpp"

#include <cmath>

namespace ucon::minco {

double durationFromTau(double tau) {
  if (tau > 0.0) return (0.5 * tau + 1.0) * tau + 1.0;
  const double den = (0.5 * tau - 1.0) * tau + 1.0;
  return 1.0 / den;
}

double durationDerivative(double tau) {
  if (tau > 0.0) return tau + 1.0;
  const double den = (0.5 * tau - 1.0) * tau + 1.0;
  return (1.0 - tau) / (den * den);
}

double tauFromDuration(double duration) {
  if (duration > 1.0) return std::sqrt(2.0 * duration - 1.0) - 1.0;
  return 1.0 - std::sqrt(2.0 / duration - 1.0);
}

}  // namespace ucon::minco
