#include "ucon/minco/banded_lu.hpp"

#include <algorithm>
#include <cmath>

namespace ucon::minco {

void BandedLu::reset(int n, int lower, int upper) {
  n_ = n;
  lower_ = lower;
  upper_ = upper;
  // Row interchanges can push fill-in up to lower + upper above the diagonal.
  width_ = 2 * lower + upper + 1;
  band_.assign(static_cast<std::size_t>(n) * width_, 0.0);
  mult_.assign(static_cast<std::size_t>(n) * std::max(lower, 1), 0.0);
  pivot_.assign(n, 0);
}

void BandedLu::setZero() { std::fill(band_.begin(), band_.end(), 0.0); }

bool BandedLu::factorise() {
  const int ue = lower_ + upper_;  // effective upper bandwidth of U
  for (int k = 0; k < n_; ++k) {
    const int last_row = std::min(n_ - 1, k + lower_);
    const int last_col = std::min(n_ - 1, k + ue);
    int p = k;
    double best = std::abs(band_[index(k, k)]);
    for (int i = k + 1; i <= last_row; ++i) {
      const double v = std::abs(band_[index(i, k)]);
      if (v > best) {
        best = v;
        p = i;
      }
    }
    pivot_[k] = p;
    if (!(best > 0.0)) return false;
    if (p != k) {
      for (int j = k; j <= last_col; ++j) std::swap(band_[index(k, j)], band_[index(p, j)]);
    }
    const double inv = 1.0 / band_[index(k, k)];
    for (int i = k + 1; i <= last_row; ++i) {
      const double m = band_[index(i, k)] * inv;
      mult_[static_cast<std::size_t>(k) * lower_ + (i - k - 1)] = m;
      band_[index(i, k)] = 0.0;
      if (m == 0.0) continue;
      for (int j = k + 1; j <= last_col; ++j) band_[index(i, j)] -= m * band_[index(k, j)];
    }
  }
  return true;
}

// The solves run over all columns of B at once (a step for every column before the next
// step): each column sees the same operations in the same order as on its own, and the
// band's entries are loaded once per step instead of once per column.
void BandedLu::solve(Eigen::Ref<Eigen::MatrixXd> b) const {
  const int ue = lower_ + upper_;
  const int nc = static_cast<int>(b.cols());
  for (int k = 0; k < n_; ++k) {  // forward: L_k^-1 P_k
    if (pivot_[k] != k) b.row(k).swap(b.row(pivot_[k]));
    const int last_row = std::min(n_ - 1, k + lower_);
    for (int i = k + 1; i <= last_row; ++i) {
      const double m = mult_[static_cast<std::size_t>(k) * lower_ + (i - k - 1)];
      for (int c = 0; c < nc; ++c) b(i, c) -= m * b(k, c);
    }
  }
  for (int k = n_ - 1; k >= 0; --k) {  // back substitution with U
    const int last_col = std::min(n_ - 1, k + ue);
    const double d = band_[index(k, k)];
    for (int c = 0; c < nc; ++c) {
      double s = b(k, c);
      for (int j = k + 1; j <= last_col; ++j) s -= band_[index(k, j)] * b(j, c);
      b(k, c) = s / d;
    }
  }
}

void BandedLu::solveTransposed(Eigen::Ref<Eigen::MatrixXd> b) const {
  // A = M^-1 U with M = L_{n-1}^-1 P_{n-1} ... L_0^-1 P_0, so A^T x = b is U^T y = b, x = M^T y.
  const int ue = lower_ + upper_;
  const int nc = static_cast<int>(b.cols());
  for (int k = 0; k < n_; ++k) {  // forward substitution with U^T
    const int first = std::max(0, k - ue);
    const double d = band_[index(k, k)];
    for (int c = 0; c < nc; ++c) {
      double s = b(k, c);
      for (int j = first; j < k; ++j) s -= band_[index(j, k)] * b(j, c);
      b(k, c) = s / d;
    }
  }
  for (int k = n_ - 1; k >= 0; --k) {  // apply P_k^T L_k^-T in reverse order
    const int last_row = std::min(n_ - 1, k + lower_);
    for (int c = 0; c < nc; ++c) {
      double s = 0.0;
      for (int i = k + 1; i <= last_row; ++i)
        s += mult_[static_cast<std::size_t>(k) * lower_ + (i - k - 1)] * b(i, c);
      b(k, c) -= s;
    }
    if (pivot_[k] != k) b.row(k).swap(b.row(pivot_[k]));
  }
}

}  // namespace ucon::minco
