#pragma once
/// @file fast_atan2.hpp
/// atan2 to within 2e-5 rad, for binning directions into angular cells of a degree or more.
///
/// libm's atan2 is exact to the last bit and was ~5 % of the whole navigation pipeline's CPU
/// (perception bins every return by azimuth and elevation, several times per frame). This is
/// the odd polynomial of Abramowitz & Stegun 4.4.47 on [0, 1] (|error| about 1e-5 rad), folded
/// out to the full circle. Plain arithmetic: the same inputs give the same bits everywhere.

#include <cmath>

namespace ucon {

/// Angle of (x, y) in [-pi, pi], like std::atan2 to within 2e-5 rad; 0 for (0, 0). A zero y
/// with negative x gives +pi (std::atan2 gives -pi for y = -0.0).
inline double fastAtan2(double y, double x) {
  constexpr double kPi = 3.14159265358979323846;
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (!(hi > 0.0)) return hi == 0.0 ? 0.0 : std::atan2(y, x);  // (0, 0), or NaN passed through
  const double a = lo / hi, s = a * a;
  double r = a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))));
  if (ay > ax) r = 0.5 * kPi - r;
  if (x < 0.0) r = kPi - r;
  return y < 0.0 ? -r : r;
}

}  // namespace ucon
