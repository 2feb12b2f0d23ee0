#pragma once
/// @file minco_band_lu.hpp
/// The LU factorisation with partial pivoting of MinimumJerk2D's 6N x 6N band (6 sub- and
/// 5 super-diagonals), specialised for speed: the bandwidths are compile-time constants, the
/// two right-hand sides (x, y) are solved together as pairs, and zero rows pad the band on
/// both sides so that every step runs a fixed number of operations.
///
/// Its results equal BandedLu's on the same matrix bit for bit whenever they are finite: the
/// same pivots and the same operations on every non-zero, in the same order. It skips only
/// terms that are exactly zero where skipping cannot change a result (see the .cpp).

#include <vector>

#include <Eigen/Core>

namespace ucon::minco {

class MincoBandLu {
 public:
  static constexpr int kLower = 6;                 ///< sub-diagonals
  static constexpr int kUpper = 5;                 ///< super-diagonals
  static constexpr int kFill = kLower + kUpper;    ///< super-diagonals of U (row interchanges)
  static constexpr int kPad = kFill;               ///< zero rows before and after the band

  /// Right-hand sides and solutions: row kPad + i holds row i (x, y); the kPad rows before
  /// and after must be zero (the solves keep them so).
  using Pairs = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

  /// Allocates an n x n matrix (n >= 1), zeroed.
  void reset(int n);
  /// Zeroes all entries (keeps the allocation).
  void setZero();
  int size() const { return n_; }
  /// A zero pairs buffer for this size: n + 2 kPad rows.
  Pairs makePairs() const { return Pairs::Zero(n_ + 2 * kPad, 2); }

  /// Entry (i, j); requires -kLower <= j - i <= kUpper before factorise().
  double& operator()(int i, int j) { return diag(i)[j - i]; }
  double operator()(int i, int j) const { return diag(i)[j - i]; }

  /// In-place factorisation P A = L U with row interchanges. Returns false if a pivot is
  /// zero (the matrix is singular); the solves are then undefined.
  bool factorise();
  /// Solves A X = B in place (B as described for Pairs).
  void solve(Pairs& xy) const;
  /// Solves A^T X = B in place.
  void solveTransposed(Pairs& xy) const;

 private:
  static constexpr int kWidth = kLower + kFill + 1;  // stored columns per row: i-6 ... i+11
  static constexpr int kDown = kWidth - 1;           // from A(i, j) to A(i + 1, j)
  // diag(i)[o] = A(i, i + o), o in [-kLower, kFill]; rows -kPad ... n-1+kPad exist.
  double* diag(int i) { return band_.data() + static_cast<std::ptrdiff_t>(i + kPad) * kWidth + kLower; }
  const double* diag(int i) const {
    return band_.data() + static_cast<std::ptrdiff_t>(i + kPad) * kWidth + kLower;
  }

  int n_ = 0;
  bool wide_ = false;         // some row of U reaches beyond 6 super-diagonals
  std::vector<double> band_;  // row-major band with kPad zero rows on both sides
  std::vector<double> mult_;  // mult_[6 k + d - 1]: multiplier of row k + d at step k
  std::vector<int> pivot_;    // row swapped with row k at step k
};

}  // namespace ucon::minco
