#pragma once
/// @file minco_system.hpp
/// The 6N x 6N linear system M(T) c = b of MINCO minimum jerk (s = 3) and its LU
/// factorisation, for MinimumJerk2D.
///
/// Unknowns: c_{i,j} (piece i, power j) in column 6i + j. Equations (rows), in the order that
/// makes elimination without row interchanges stable (the order of Wang et al.'s reference
/// implementation; the pivots are 1, 1, 2 (head), 6, 24 (jerk, snap), the waypoint's,
/// -1, -1, -2 (position, velocity, acceleration), and three for the tail):
///   rows 0..2            head: c_{0,0} = p, c_{0,1} = v, 2 c_{0,2} = a;
///   rows 6i+3 ... 6i+8   junction i (0 <= i < N-1), at t = T_i of piece i and t = 0 of
///                        piece i+1: jerk continuity, snap continuity, waypoint p_i(T_i) = q_i,
///                        position, velocity and acceleration continuity;
///   rows 6N-3 ... 6N-1   tail: p, v, a of piece N-1 at T_{N-1}.
/// The right-hand side b is zero except in the head, waypoint and tail rows.
///
/// "Set up once, compute often": setPieces() works out, once per N, where the factors are
/// non-zero (the same for every T); setDurations() then builds and factorises M(T) touching
/// only those entries, and the solves do the same. Nothing allocates after setPieces().
/// The two right-hand sides (x and y) are solved together, stored as pairs.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace ucon::minco {

class MincoSystem {
 public:
  /// Right-hand sides and solutions, one row (x, y) per equation or unknown: 6N x 2.
  using Pairs = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

  /// Derivative order of each junction row (jerk, snap, waypoint, p, v, a continuity).
  static constexpr int kJunctionDerivative[6] = {3, 4, 0, 0, 1, 2};
  /// Row of the head condition of derivative order d (0..2).
  static constexpr int headRow(int d) { return d; }
  /// Row of the waypoint q_i (0 <= i < N-1).
  static constexpr int waypointRow(int i) { return 6 * i + 5; }
  /// First row of junction i.
  static constexpr int junctionRow(int i) { return 6 * i + 3; }
  /// Row of the tail condition of derivative order d (0..2).
  int tailRow(int d) const { return 6 * n_ - 3 + d; }

  /// Allocates for `pieces` >= 1 and finds the non-zero pattern of the factors.
  void setPieces(int pieces);
  int pieces() const { return n_; }

  /// Builds M(T) for the durations T (N values > 0) and factorises it, M = L U. Returns
  /// false if a pivot is zero or not finite (the solves are then undefined).
  bool setDurations(const Eigen::VectorXd& T);
  /// Solves M X = B in place.
  void solve(Pairs& b) const;
  /// Solves M^T X = B in place.
  void solveTransposed(Pairs& b) const;

 private:
  static constexpr int kLower = 6, kUpper = 6;      // bandwidths of M, L and U
  static constexpr int kWidth = kLower + kUpper + 1;
  static constexpr int kDown = kWidth - 1;          // from A(i, j) to A(i + 1, j)
  // diag(i)[o] = A(i, i + o), o in [-kLower, kUpper].
  double* diag(int i) { return band_.data() + static_cast<std::size_t>(i) * kWidth + kLower; }
  const double* diag(int i) const { return band_.data() + static_cast<std::size_t>(i) * kWidth + kLower; }

  struct ListStep;
  ListStep listStep(int k) const;
  template <typename F>
  void forEachStep(F&& step) const;
  template <typename F>
  void forEachStepReversed(F&& step) const;

  int n_ = 0;                     // pieces
  int rows_ = 0;                  // 6N
  std::vector<double> band_;      // M, then L (unit diagonal) and U in place, row-major band
  std::vector<double> inv_diag_;  // 1 / U(k, k)
  // Step k of the elimination: rows k + below_[e] for e in [below_begin_[k], below_begin_[k+1])
  // have a multiplier, columns k + right_[e] for e in [right_begin_[k], right_begin_[k+1]) of
  // row k of U are non-zero (in increasing order).
  std::vector<std::uint8_t> below_, right_;
  std::vector<int> below_begin_, right_begin_;
  std::vector<int> fill_;         // band offsets of fill-in, zeroed before each build
  int periodic_end_ = 0;          // steps [3, periodic_end_) follow the junction pattern
};

}  // namespace ucon::minco
