#include "ucon/minco/minco_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ucon::minco {

namespace {

// j! / (j - d)!: coefficient of t^(j-d) in the d-th derivative of t^j.
constexpr double kFall[6][6] = {
    {1, 0, 0, 0, 0, 0},   {1, 1, 0, 0, 0, 0},    {1, 2, 2, 0, 0, 0},
    {1, 3, 6, 6, 0, 0},   {1, 4, 12, 24, 24, 0}, {1, 5, 20, 60, 120, 120}};

using Pair = Eigen::Array2d;
using PairMap = Eigen::Map<Pair, Eigen::Aligned16>;

// Calls put(row, column, value) for every structural non-zero of M(T).
template <typename Put>
void forEachEntry(const Eigen::VectorXd& T, int n, Put&& put) {
  put(0, 0, 1.0);
  put(1, 1, 1.0);
  put(2, 2, 2.0);
  for (int i = 0; i < n; ++i) {
    double tp[6];  // 1, T, ..., T^5
    tp[0] = 1.0;
    for (int k = 1; k < 6; ++k) tp[k] = tp[k - 1] * T(i);
    const int col = 6 * i;
    if (i + 1 < n) {
      const int r = MincoSystem::junctionRow(i);
      for (int k = 0; k < 6; ++k) {
        const int d = MincoSystem::kJunctionDerivative[k];
        for (int j = d; j < 6; ++j) put(r + k, col + j, kFall[j][d] * tp[j - d]);
        if (r + k != MincoSystem::waypointRow(i)) put(r + k, col + 6 + d, -kFall[d][d]);
      }
    } else {
      for (int d = 0; d < 3; ++d)
        for (int j = d; j < 6; ++j) put(6 * n - 3 + d, col + j, kFall[j][d] * tp[j - d]);
    }
  }
}

// Steps 6i+3 ... 6i+8 of every junction but the last one (jerk, snap and waypoint rows of
// junction i, then p, v, a rows of junction i) have the same pattern; as compile-time
// constants, the compiler unrolls them. setPieces() checks that the pattern is this one.
struct JunctionPattern {
  int nb;
  int below[4];
  int nr;
  int right[3];
};
constexpr JunctionPattern kJunctionSteps[6] = {
    {4, {2, 3, 4, 5}, 3, {1, 2, 6}},  // jerk continuity
    {4, {1, 2, 3, 4}, 2, {1, 6, 0}},  // snap continuity
    {3, {1, 2, 3, 0}, 2, {4, 5, 0}},  // waypoint
    {2, {5, 6, 0, 0}, 2, {3, 4, 0}},  // position continuity (its U entries end up exactly 0)
    {3, {4, 5, 6, 0}, 2, {2, 3, 0}},  // velocity continuity
    {4, {3, 4, 5, 6}, 2, {1, 2, 0}},  // acceleration continuity
};
template <int S>
struct JunctionStep {
  static constexpr int nb = kJunctionSteps[S].nb;
  static constexpr int nr = kJunctionSteps[S].nr;
  static constexpr int below(int e) { return kJunctionSteps[S].below[e]; }
  static constexpr int right(int e) { return kJunctionSteps[S].right[e]; }
};

}  // namespace

// The pattern of one step k of the elimination, as found by setPieces(): rows k + below(e)
// of L and columns k + right(e) of row k of U are non-zero (offsets increasing).
struct MincoSystem::ListStep {
  const std::uint8_t* b;
  int nb;
  const std::uint8_t* r;
  int nr;
  int below(int e) const { return b[e]; }
  int right(int e) const { return r[e]; }
};

void MincoSystem::setPieces(int pieces) {
  n_ = pieces;
  rows_ = 6 * pieces;
  band_.assign(static_cast<std::size_t>(rows_) * kWidth, 0.0);
  inv_diag_.assign(rows_, 0.0);

  // Symbolic elimination on the pattern of M (values play no part: any T will do).
  std::vector<char> nz(band_.size(), 0);
  auto at = [&](int i, int j) -> char& { return nz[static_cast<std::size_t>(i) * kWidth + kLower + (j - i)]; };
  forEachEntry(Eigen::VectorXd::Ones(n_), n_, [&](int i, int j, double) { at(i, j) = 1; });
  const std::vector<char> original = nz;
  below_.clear();
  right_.clear();
  below_begin_.assign(rows_ + 1, 0);
  right_begin_.assign(rows_ + 1, 0);
  for (int k = 0; k < rows_; ++k) {
    below_begin_[k] = static_cast<int>(below_.size());
    right_begin_[k] = static_cast<int>(right_.size());
    const int last = std::min(rows_ - 1, k + kUpper);
    for (int j = k + 1; j <= last; ++j)
      if (at(k, j)) right_.push_back(static_cast<std::uint8_t>(j - k));
    for (int i = k + 1; i <= std::min(rows_ - 1, k + kLower); ++i) {
      if (!at(i, k)) continue;
      below_.push_back(static_cast<std::uint8_t>(i - k));
      for (int j = k + 1; j <= last; ++j)
        if (at(k, j)) at(i, j) = 1;
    }
  }
  below_begin_[rows_] = static_cast<int>(below_.size());
  right_begin_[rows_] = static_cast<int>(right_.size());
  fill_.clear();
  for (std::size_t e = 0; e < nz.size(); ++e)
    if (nz[e] && !original[e]) fill_.push_back(static_cast<int>(e));

  // Junctions 0 ... N-3 (steps 3 ... 6N-10) follow kJunctionSteps: check it, step by step.
  periodic_end_ = 3;
  for (int first = 3; first + 6 <= 6 * (n_ - 1) - 3; first += 6) {
    bool same = true;
    for (int s = 0; s < 6; ++s) {
      const ListStep st = listStep(first + s);
      const JunctionPattern& p = kJunctionSteps[s];
      same = same && st.nb == p.nb && st.nr == p.nr;
      for (int e = 0; same && e < p.nb; ++e) same = st.below(e) == p.below[e];
      for (int e = 0; same && e < p.nr; ++e) same = st.right(e) == p.right[e];
    }
    if (!same) break;
    periodic_end_ = first + 6;
  }
}

namespace {

constexpr int kDown = 12;  // MincoSystem's band: from A(i, j) to A(i + 1, j)

// Eliminates column k below the pivot rk[0] = A(k, k); stores L in place and 1 / U(k, k).
template <typename Step>
inline bool factorStep(double* rk, double* inv_diag, const Step& st) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double inv = 1.0 / rk[0];
  *inv_diag = inv;
  for (int e = 0; e < st.nb; ++e) {
    double* const ri = rk + st.below(e) * kDown;  // ri[o] = A(k + d, k + o)
    const double m = ri[0] * inv;
    ri[0] = m;
    for (int f = 0; f < st.nr; ++f) ri[st.right(f)] -= m * rk[st.right(f)];
  }
  return std::abs(rk[0]) < kInf && std::abs(inv) < kInf;
}

using Pair = Eigen::Array2d;
using PairMap = Eigen::Map<Pair, Eigen::Aligned16>;

// Step k of L y = b (column k of L) on the pairs x = &b(k).
template <typename Step>
inline void forwardStep(const double* lk, double* x, const Step& st) {
  const Pair xk = PairMap(x);
  for (int e = 0; e < st.nb; ++e) PairMap(x + 2 * st.below(e)) -= lk[st.below(e) * kDown] * xk;
}

// Step k of U x = y (row k of U, the newest value last).
template <typename Step>
inline void backStep(const double* rk, double inv, double* x, const Step& st) {
  PairMap xk(x);
  Pair s = xk;
  for (int f = st.nr - 1; f >= 0; --f) s -= rk[st.right(f)] * PairMap(x + 2 * st.right(f));
  xk = s * inv;
}

// Step k of U^T y = b (row k of U as a column of U^T).
template <typename Step>
inline void forwardTransposedStep(const double* rk, double inv, double* x, const Step& st) {
  PairMap xk(x);
  const Pair yk = xk * inv;
  xk = yk;
  for (int f = 0; f < st.nr; ++f) PairMap(x + 2 * st.right(f)) -= rk[st.right(f)] * yk;
}

// Step k of L^T x = y (column k of L as a row of L^T, the newest value last).
template <typename Step>
inline void backTransposedStep(const double* lk, double* x, const Step& st) {
  PairMap xk(x);
  Pair s = xk;
  for (int e = st.nb - 1; e >= 0; --e) s -= lk[st.below(e) * kDown] * PairMap(x + 2 * st.below(e));
  xk = s;
}

// Calls step(k, pattern) for k = first, first+1, ... of one junction (6 steps).
template <typename F>
inline void junctionSteps(int first, F&& step) {
  step(first + 0, JunctionStep<0>());
  step(first + 1, JunctionStep<1>());
  step(first + 2, JunctionStep<2>());
  step(first + 3, JunctionStep<3>());
  step(first + 4, JunctionStep<4>());
  step(first + 5, JunctionStep<5>());
}

template <typename F>
inline void junctionStepsReversed(int first, F&& step) {
  step(first + 5, JunctionStep<5>());
  step(first + 4, JunctionStep<4>());
  step(first + 3, JunctionStep<3>());
  step(first + 2, JunctionStep<2>());
  step(first + 1, JunctionStep<1>());
  step(first + 0, JunctionStep<0>());
}

}  // namespace

MincoSystem::ListStep MincoSystem::listStep(int k) const {
  return {below_.data() + below_begin_[k], below_begin_[k + 1] - below_begin_[k],
          right_.data() + right_begin_[k], right_begin_[k + 1] - right_begin_[k]};
}

// Steps [0, 3) and [periodic_end_, 6N) use the lists; the junctions in between the constants.
template <typename F>
void MincoSystem::forEachStep(F&& step) const {
  const int head = std::min(3, rows_);
  for (int k = 0; k < head; ++k) step(k, listStep(k));
  for (int k = head; k < periodic_end_; k += 6) junctionSteps(k, step);
  for (int k = std::max(head, periodic_end_); k < rows_; ++k) step(k, listStep(k));
}

template <typename F>
void MincoSystem::forEachStepReversed(F&& step) const {
  const int head = std::min(3, rows_);
  for (int k = rows_ - 1; k >= std::max(head, periodic_end_); --k) step(k, listStep(k));
  for (int k = periodic_end_ - 6; k >= head; k -= 6) junctionStepsReversed(k, step);
  for (int k = head - 1; k >= 0; --k) step(k, listStep(k));
}

bool MincoSystem::setDurations(const Eigen::VectorXd& T) {
  double* const a = band_.data();
  for (int e : fill_) a[e] = 0.0;
  forEachEntry(T, n_, [&](int i, int j, double v) { diag(i)[j - i] = v; });
  bool ok = true;
  forEachStep([&](int k, const auto& st) { ok = factorStep(diag(k), &inv_diag_[k], st) && ok; });
  return ok;
}

void MincoSystem::solve(Pairs& b) const {
  double* const x = b.data();
  forEachStep([&](int k, const auto& st) { forwardStep(diag(k), x + 2 * k, st); });
  forEachStepReversed([&](int k, const auto& st) { backStep(diag(k), inv_diag_[k], x + 2 * k, st); });
}

void MincoSystem::solveTransposed(Pairs& b) const {
  double* const x = b.data();
  forEachStep([&](int k, const auto& st) { forwardTransposedStep(diag(k), inv_diag_[k], x + 2 * k, st); });
  forEachStepReversed([&](int k, const auto& st) { backTransposedStep(diag(k), x + 2 * k, st); });
}

}  // namespace ucon::minco
