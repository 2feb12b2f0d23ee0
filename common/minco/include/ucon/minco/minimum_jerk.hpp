#pragma once
/// @file minimum_jerk.hpp
/// MINCO minimum-jerk trajectory (s = 3) in 2-D (Wang et al. 2022; docs/reference.md §4).
///
/// N quintic pieces p_i(t) = sum_j c_{i,j} t^j, t in [0, T_i]. Conditions: head p/v/a,
/// tail p/v/a, N-1 inner waypoints q_i = p_i(T_i), continuity of derivatives 0..4 at each
/// inner waypoint: a 6N x 6N banded system M(T) c = b(q) solved in O(N).
///
/// "Set up once, compute often": setConditions() allocates for N pieces; setParameters()
/// rebuilds and factorises the band and solves, without allocating.
///
/// Coefficient matrix layout: coeffs() is 6N x 2, row 6i + j holds c_{i,j} (x, y) [m/s^j].

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ucon/minco/minco_system.hpp"
#include "ucon/trajectory_t.hpp"

namespace ucon::minco {

class MinimumJerk2D {
 public:
  /// Boundary state, columns position [m], velocity [m/s], acceleration [m/s^2].
  using Boundary = Eigen::Matrix<double, 2, 3>;

  /// Stores head and tail conditions and allocates for `pieces` >= 1 pieces (only when N
  /// changes). Returns false for pieces < 1 or non-finite conditions.
  bool setConditions(const Boundary& head, const Boundary& tail, int pieces);
  /// Replaces the tail condition (same N), e.g. for a moving goal.
  bool setTail(const Boundary& tail);

  /// Solves for the coefficients given inner waypoints (2 x (N-1), [m]) and durations
  /// (N, [s], each > 0). Returns false (coefficients invalid) on non-finite or non-positive
  /// input or a singular system.
  bool setParameters(const Eigen::Ref<const Eigen::Matrix2Xd>& inner,
                     const Eigen::Ref<const Eigen::VectorXd>& durations);

  int pieces() const { return n_; }
  const Eigen::MatrixXd& coeffs() const { return c_; }
  const Eigen::VectorXd& durations() const { return T_; }
  double totalDuration() const { return T_.sum(); }
  const Boundary& head() const { return head_; }
  const Boundary& tail() const { return tail_; }

  /// Closed-form jerk energy sum_i int_0^{T_i} ||p_i'''(t)||^2 dt [m^2/s^5].
  double energy() const;
  /// Adds dE/dc (6N x 2) to gC and dE/dT (N) to gT.
  void addEnergyGradient(Eigen::Ref<Eigen::MatrixXd> gC, Eigen::Ref<Eigen::VectorXd> gT) const;

  /// Propagates the partial gradient of any cost K(c, T) (gC = dK/dc with c held fixed,
  /// gT = dK/dT) to the free parameters through c = c(q, T): one transposed banded solve.
  /// Outputs dK/dq (2 x (N-1)) and the total dK/dT (N); `g_tail_position` (optional) gets
  /// dK/d(tail position). Not const: uses internal buffers.
  void propagateGradient(const Eigen::Ref<const Eigen::MatrixXd>& gC,
                         const Eigen::Ref<const Eigen::VectorXd>& gT,
                         Eigen::Ref<Eigen::Matrix2Xd> g_inner, Eigen::Ref<Eigen::VectorXd> g_durations,
                         Eigen::Vector2d* g_tail_position = nullptr);

  /// order-th derivative (0..5) of piece i at local time t [s].
  Eigen::Vector2d derivative(int piece, double t, int order) const;
  /// order-th derivative at time t [s] from the start (clamped to [0, totalDuration()]).
  Eigen::Vector2d derivativeAt(double t, int order) const;

  /// Writes the trajectory into a message: start_utime, dim = 2, order1 = 6, num_pieces,
  /// durations, coeffs (piece-major, then axis, then ascending power). Leaves utime, seq,
  /// plan_id, goal_id, status, message and yaw to the caller.
  void toTrajectory(int64_t start_utime, trajectory_t* out) const;

 private:
  int n_ = 0;
  Boundary head_ = Boundary::Zero();
  Boundary tail_ = Boundary::Zero();
  Eigen::VectorXd T_;
  Eigen::MatrixXd c_;       // 6N x 2
  MincoSystem system_;      // M(T), factorised
  MincoSystem::Pairs rhs_, adjoint_;  // 6N x 2 work buffers of the two solves
};

}  // namespace ucon::minco
