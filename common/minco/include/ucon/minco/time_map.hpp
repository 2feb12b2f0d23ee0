#pragma once
/// @file time_map.hpp
/// Smooth bijection between an unconstrained variable tau and a positive duration T
/// (docs/reference.md §4): T = tau^2/2 + tau + 1 for tau > 0, T = 1/(tau^2/2 - tau + 1) otherwise.
/// C^1 at tau = 0 (T = 1, dT/dtau = 1), so L-BFGS can work on tau without bounds.

namespace ucon::minco {

/// Duration T(tau) [s], > 0 for every finite tau.
double durationFromTau(double tau);
/// dT/dtau [s per unit tau].
double durationDerivative(double tau);
/// Inverse map: tau(T) for T > 0.
double tauFromDuration(double duration);

}  // namespace ucon::minco
