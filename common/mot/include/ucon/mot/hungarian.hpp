#pragma once
/// @file hungarian.hpp
/// Minimum-cost assignment (Hungarian method, shortest augmenting paths with potentials,
/// O(n^2 m)) on a rectangular cost matrix with forbidden pairs. Header-only and free of
/// third-party types so that CLEAR-MOT and perception's data association share it.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace ucon {

/// A rows x cols cost matrix, row-major. A non-finite entry (inf or NaN) marks a forbidden
/// pair.
struct CostMatrix {
  int rows = 0;
  int cols = 0;
  std::vector<double> values;  ///< size rows*cols

  CostMatrix() = default;
  /// A matrix filled with `fill` (default: every pair forbidden).
  CostMatrix(int r, int c, double fill = std::numeric_limits<double>::infinity())
      : rows(r), cols(c), values(static_cast<std::size_t>(r) * static_cast<std::size_t>(c), fill) {}
  double& operator()(int r, int c) { return values[static_cast<std::size_t>(r) * cols + c]; }
  double operator()(int r, int c) const { return values[static_cast<std::size_t>(r) * cols + c]; }
};

/// Solves the assignment problem on `cost`.
///
/// Among all assignments it first maximises the number of allowed (finite-cost) pairs, then
/// minimises their total cost — the behaviour CLEAR-MOT tools expect when distances beyond
/// the threshold are forbidden. Returns, for each row, the assigned column or -1. Each column
/// is used at most once. Ties are broken deterministically (lowest index first).
inline std::vector<int> solveAssignment(const CostMatrix& cost) {
  const int R = cost.rows;
  const int C = cost.cols;
  std::vector<int> result(static_cast<std::size_t>(std::max(R, 0)), -1);
  if (R <= 0 || C <= 0) return result;

  // Forbidden pairs get a cost so large that using one fewer always beats any finite saving:
  // big > (number of pairs in an assignment) * (spread of finite costs).
  double max_abs = 0.0;
  bool any_finite = false;
  for (double v : cost.values) {
    if (std::isfinite(v)) {
      max_abs = std::max(max_abs, std::fabs(v));
      any_finite = true;
    }
  }
  if (!any_finite) return result;
  const int k = std::min(R, C);
  const double big = (2.0 * max_abs + 1.0) * static_cast<double>(k + 1);

  // Work on an n x m matrix with n <= m (transpose when there are more rows than columns).
  const bool transposed = R > C;
  const int n = transposed ? C : R;
  const int m = transposed ? R : C;
  auto at = [&](int i, int j) {  // i in [0,n), j in [0,m)
    const double v = transposed ? cost(j, i) : cost(i, j);
    return std::isfinite(v) ? v : big;
  };

  // Classic potentials formulation, 1-based with a virtual column 0.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(static_cast<std::size_t>(n) + 1, 0.0), v(static_cast<std::size_t>(m) + 1, 0.0);
  std::vector<int> p(static_cast<std::size_t>(m) + 1, 0), way(static_cast<std::size_t>(m) + 1, 0);
  std::vector<double> minv(static_cast<std::size_t>(m) + 1);
  std::vector<char> used(static_cast<std::size_t>(m) + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = at(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }

  for (int j = 1; j <= m; ++j) {
    if (p[j] == 0) continue;
    const int i = p[j] - 1;
    const int jj = j - 1;
    const int r = transposed ? jj : i;
    const int c = transposed ? i : jj;
    if (std::isfinite(cost(r, c))) result[static_cast<std::size_t>(r)] = c;
  }
  return result;
}

}  // namespace ucon
