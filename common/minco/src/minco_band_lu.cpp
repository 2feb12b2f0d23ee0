#include "ucon/minco/minco_band_lu.hpp"

#include <algorithm>
#include <cmath>

namespace ucon::minco {

// Why the results are BandedLu's, bit for bit, whenever they are finite:
// - factorise() makes the same pivot choices and the same updates, over the full width of U
//   (11 super-diagonals) for every row; columns past the matrix (padding) hold +0.0, and
//   `x -= m * (+0.0)` leaves x as it is (the band never holds -0.0, since a difference is
//   -0.0 only when its first operand is);
// - the solves run the same steps on every row in the same order. Terms with a padding row
//   or column are +0.0 * +0.0 and leave every sum as it is. Beyond 6 super-diagonals U is
//   exactly +0.0 (checked: wide_ otherwise), and `s - (±0.0)` equals s unless s is -0.0,
//   which a row's sum can only be if it starts at zero: such a row runs over the full width.
// Non-finite values can make results differ (0 * inf is NaN where a skipped term is not);
// MinimumJerk2D checks its results and falls back to BandedLu then.

namespace {
using Pair = Eigen::Array2d;
using PairMap = Eigen::Map<Pair>;
using Row = Eigen::Map<Eigen::Array<double, MincoBandLu::kFill, 1>>;  // A(i, k+1 ... k+11)
}  // namespace

void MincoBandLu::reset(int n) {
  n_ = n;
  band_.assign(static_cast<std::size_t>(n + 2 * kPad) * kWidth, 0.0);
  mult_.assign(static_cast<std::size_t>(n) * kLower, 0.0);
  pivot_.assign(n, 0);
  wide_ = false;
}

void MincoBandLu::setZero() {
  std::fill(band_.begin() + kPad * kWidth, band_.end() - kPad * kWidth, 0.0);
}

bool MincoBandLu::factorise() {
  wide_ = false;
  for (int k = 0; k < n_; ++k) {
    double* const rk = diag(k);
    // Column k below the diagonal: A(k + d, k) = rk[d * kDown]; rows past n are zero and
    // never win (strictly greater).
    int p = 0;
    double best = std::abs(rk[0]);
    for (int d = 1; d <= kLower; ++d) {
      const double v = std::abs(rk[d * kDown]);
      if (v > best) {
        best = v;
        p = d;
      }
    }
    pivot_[k] = k + p;
    if (!(best > 0.0)) return false;
    if (p != 0) {
      Eigen::Map<Eigen::Array<double, kFill + 1, 1>> a(rk), b(rk + p * kDown);
      const Eigen::Array<double, kFill + 1, 1> t = a;
      a = b;
      b = t;
    }
    // Row k of U is final now.
    for (int o = kLower + 1; o <= kFill; ++o) wide_ = wide_ || rk[o] != 0.0;
    const double inv = 1.0 / rk[0];
    double* const mk = mult_.data() + static_cast<std::size_t>(k) * kLower;
    const Row uk(rk + 1);
    const int rows = std::min(n_ - 1, k + kLower) - k;
    for (int d = 1; d <= rows; ++d) {
      double* const ri = rk + d * kDown;  // ri[o] = A(k + d, k + o)
      const double m = ri[0] * inv;
      mk[d - 1] = m;
      ri[0] = 0.0;
      if (m == 0.0) continue;
      Row(ri + 1) -= m * uk;
    }
  }
  return true;
}

void MincoBandLu::solve(Pairs& xy) const {
  auto x = [&](int i) { return PairMap(xy.data() + 2 * (i + kPad)); };
  for (int k = 0; k < n_; ++k) {  // forward: L_k^-1 P_k
    if (pivot_[k] != k) {
      const Pair t = x(k);
      x(k) = x(pivot_[k]);
      x(pivot_[k]) = t;
    }
    const Pair xk = x(k);
    const double* const mk = mult_.data() + static_cast<std::size_t>(k) * kLower;
    for (int d = 1; d <= kLower; ++d) x(k + d) -= mk[d - 1] * xk;
  }
  for (int k = n_ - 1; k >= 0; --k) {  // back substitution with U
    const double* const rk = diag(k);
    Pair s = x(k);
    const int width = (wide_ || s(0) == 0.0 || s(1) == 0.0) ? kFill : kLower;
    for (int o = 1; o <= width; ++o) s -= rk[o] * x(k + o);
    x(k) = s / rk[0];
  }
}

void MincoBandLu::solveTransposed(Pairs& xy) const {
  // A = M^-1 U with M = L_{n-1}^-1 P_{n-1} ... L_0^-1 P_0, so A^T x = b is U^T y = b, x = M^T y.
  auto x = [&](int i) { return PairMap(xy.data() + 2 * (i + kPad)); };
  for (int k = 0; k < n_; ++k) {  // forward substitution with U^T
    const double* const ck = diag(k);  // ck[-(k - j) * kDown] = U(j, k)
    Pair s = x(k);
    const int width = (wide_ || s(0) == 0.0 || s(1) == 0.0) ? kFill : kLower;
    for (int j = k - width; j < k; ++j) s -= ck[-(k - j) * kDown] * x(j);
    x(k) = s / ck[0];
  }
  for (int k = n_ - 1; k >= 0; --k) {  // apply P_k^T L_k^-T in reverse order
    const double* const mk = mult_.data() + static_cast<std::size_t>(k) * kLower;
    Pair s = Pair::Zero();
    for (int d = 1; d <= kLower; ++d) s += mk[d - 1] * x(k + d);
    x(k) -= s;
    if (pivot_[k] != k) {
      const Pair t = x(k);
      x(k) = x(pivot_[k]);
      x(pivot_[k]) = t;
    }
  }
}

}  // namespace ucon::minco
