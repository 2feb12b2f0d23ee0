#pragma once
/// @file banded_lu.hpp
/// LU factorisation with partial pivoting of a square banded matrix, O(n·kl·(kl+ku)), with
/// solves of A x = b and A^T x = b. Storage is allocated by reset() (when the size changes);
/// factorise() and the solves do not allocate.

#include <vector>

#include <Eigen/Core>

namespace ucon::minco {

class BandedLu {
 public:
  /// Allocates an n x n matrix with `lower` sub-diagonals and `upper` super-diagonals, zeroed.
  void reset(int n, int lower, int upper);
  /// Zeroes all entries (keeps the allocation).
  void setZero();

  int size() const { return n_; }
  /// Entry (i, j); requires -lower <= j - i <= upper before factorise().
  double& operator()(int i, int j) { return band_[index(i, j)]; }
  double operator()(int i, int j) const { return band_[index(i, j)]; }

  /// In-place factorisation P A = L U with row interchanges. Returns false if a pivot is zero
  /// (the matrix is singular); the solves are then undefined.
  bool factorise();
  /// Solves A X = B in place for every column of B (n rows).
  void solve(Eigen::Ref<Eigen::MatrixXd> b) const;
  /// Solves A^T X = B in place for every column of B (n rows).
  void solveTransposed(Eigen::Ref<Eigen::MatrixXd> b) const;

 private:
  int index(int i, int j) const { return i * width_ + (j - i + lower_); }
  int n_ = 0, lower_ = 0, upper_ = 0, width_ = 0;
  std::vector<double> band_;     // row-major band, columns i-lower ... i+lower+upper
  std::vector<double> mult_;     // elimination multipliers, mult_[k*lower + m] for row k+1+m
  std::vector<int> pivot_;       // row swapped with row k at step k
};

}  // namespace ucon::minco
