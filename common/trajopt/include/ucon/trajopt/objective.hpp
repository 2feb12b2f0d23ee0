#pragma once
/// @file objective.hpp
/// The whole sector-MINCO objective J(q, τ) = ∫||p'''||^2 + ρ ΣT + ∫(static + velocity +
/// acceleration penalties + λ_d J_d) dt over x = [q_0x q_0y ... q_{N-2}y, τ_0 ... τ_{N-1}]
/// (inner waypoints [m], then unconstrained time variables, T = T(τ) of minco/time_map.hpp),
/// with its analytic gradient through MINCO. The penalty integrals use the paper's trapezoid
/// weights (eq. 14): T_i/L · (1/2, 1, ..., 1, 1/2) over L + 1 samples per piece.
/// A solver sees only evaluate(x, grad).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ucon/minco/minimum_jerk.hpp"
#include "ucon/trajopt/cost_terms.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon::trajopt {

class SectorMincoObjective {
 public:
  SectorMincoObjective(const OptimizerParams& params, const kalman::KalmanParams& prediction);

  /// Sets up one problem (allocates only when N or the obstacle count grows). Returns an
  /// empty string on success, otherwise what is wrong with the request.
  std::string setup(const PlanRequest& request);

  int dimension() const { return 3 * n_ - 2; }
  int pieces() const { return n_; }
  /// x of the request's initial guess.
  Eigen::VectorXd initialGuess() const;
  /// J(x); writes ∇J into grad (dimension() entries) when grad is not null. Allocation-free.
  /// Returns +inf-like 1e300 with zero gradient if MINCO cannot be solved at x.
  double evaluate(const double* x, double* grad);

  /// Breakdown of the last evaluate().
  const CostBreakdown& breakdown() const { return breakdown_; }
  /// MINCO state of the last evaluate().
  const minco::MinimumJerk2D& trajectory() const { return minco_; }
  /// Splits x into waypoints and durations [s].
  void decode(const double* x, std::vector<Eigen::Vector2d>* inner, std::vector<double>* durations) const;

  /// Obstacles kept after the corridor cull of the last setup().
  const std::vector<ObstacleTrack>& tracks() const { return tracks_; }
  int obstaclesRejected() const { return rejected_; }
  int obstaclesWithoutCovariance() const { return without_covariance_; }

 private:
  OptimizerParams params_;
  kalman::KalmanParams prediction_;
  const DistanceField2D* field_ = nullptr;
  int n_ = 0;
  int samples_ = 0;  // L
  minco::MinimumJerk2D minco_;
  Eigen::Matrix2Xd inner0_;
  Eigen::VectorXd T0_;
  std::vector<ObstacleTrack> tracks_;
  int rejected_ = 0, without_covariance_ = 0;
  // Buffers of evaluate().
  Eigen::Matrix2Xd q_, g_inner_;
  Eigen::VectorXd T_, dT_dtau_, gT_, gT_total_, time_tail_;
  Eigen::MatrixXd gC_;
  std::vector<int> candidates_;       // per piece: indices into tracks_
  std::vector<int> candidate_begin_;  // n_ + 1 offsets into candidates_
  CostBreakdown breakdown_;
};

}  // namespace ucon::trajopt
