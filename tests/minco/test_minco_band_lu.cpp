#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "ucon/minco/banded_lu.hpp"
#include "ucon/minco/minco_band_lu.hpp"

using ucon::minco::BandedLu;
using ucon::minco::MincoBandLu;

namespace {

// The same random 6/5-band matrix in both solvers. dominant: a heavy diagonal (no row
// interchanges, U keeps 5 super-diagonals); otherwise zeros on every third diagonal entry
// (row interchanges, fill-in up to 11 super-diagonals).
void fillBoth(int n, bool dominant, unsigned seed, BandedLu* a, MincoBandLu* b) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  a->reset(n, MincoBandLu::kLower, MincoBandLu::kUpper);
  b->reset(n);
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - MincoBandLu::kLower); j <= std::min(n - 1, i + MincoBandLu::kUpper); ++j) {
      double v = u(rng);
      if (i == j) v = dominant ? 20.0 + v : (i % 3 == 0 ? 0.0 : v);
      if (std::abs(v) < 0.2 && i != j) v = 0.0;  // some zeros inside the band
      (*a)(i, j) = v;
      (*b)(i, j) = v;
    }
}

// Right-hand sides with exact zeros of both signs (the case where skipping +0 terms could
// change the sign of a zero result).
Eigen::MatrixXd rightHandSides(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd r(n, 2);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 2; ++c) r(i, c) = (i % 5 == 1) ? 0.0 : (i % 7 == 2 ? -0.0 : u(rng));
  r.col(1).segment(0, n / 2).setZero();
  return r;
}

bool bitwiseEqual(const Eigen::MatrixXd& a, const MincoBandLu::Pairs& b) {
  for (int i = 0; i < a.rows(); ++i)
    for (int c = 0; c < 2; ++c) {
      const double x = a(i, c), y = b(MincoBandLu::kPad + i, c);
      if (std::memcmp(&x, &y, sizeof x) != 0) return false;
    }
  return true;
}

}  // namespace

TEST(MincoBandLu, GivenBandMatricesWithAndWithoutRowInterchangesThenSolvesEqualBandedLuBitForBit) {
  for (bool dominant : {true, false}) {
    for (int n : {6, 12, 31, 96}) {
      for (unsigned seed = 1; seed <= 4; ++seed) {
        BandedLu ref;
        MincoBandLu fast;
        fillBoth(n, dominant, seed + 10 * n, &ref, &fast);
        const bool ok = ref.factorise();
        ASSERT_EQ(fast.factorise(), ok);
        if (!ok) continue;
        const Eigen::MatrixXd rhs = rightHandSides(n, seed);
        Eigen::MatrixXd x = rhs, y = rhs;
        ref.solve(x);
        ref.solveTransposed(y);
        MincoBandLu::Pairs px = fast.makePairs(), py = fast.makePairs();
        px.middleRows(MincoBandLu::kPad, n) = rhs;
        py.middleRows(MincoBandLu::kPad, n) = rhs;
        fast.solve(px);
        fast.solveTransposed(py);
        EXPECT_TRUE(bitwiseEqual(x, px)) << "solve, n " << n << " seed " << seed << " dominant " << dominant;
        EXPECT_TRUE(bitwiseEqual(y, py)) << "transposed, n " << n << " seed " << seed << " dominant " << dominant;
        // The padding rows stay zero.
        EXPECT_TRUE(px.topRows(MincoBandLu::kPad).isZero(0.0));
        EXPECT_TRUE(px.bottomRows(MincoBandLu::kPad).isZero(0.0));
        EXPECT_TRUE(py.topRows(MincoBandLu::kPad).isZero(0.0));
        EXPECT_TRUE(py.bottomRows(MincoBandLu::kPad).isZero(0.0));
      }
    }
  }
}

TEST(MincoBandLu, GivenASingularMatrixWhenFactorisedThenReportsFailure) {
  MincoBandLu lu;
  lu.reset(4);
  lu(0, 0) = 1;
  lu(1, 1) = 1;
  lu(3, 3) = 1;  // row 2 and column 2 empty
  EXPECT_FALSE(lu.factorise());
}
