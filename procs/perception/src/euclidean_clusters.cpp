#include "ucon/perception/euclidean_clusters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ucon {
namespace perception {

namespace {
/// Largest dense column table [columns] (16 MB of ints); a sparser cloud looks its columns up by
/// binary search instead.
constexpr int64_t kDenseLimit = int64_t(1) << 22;
}  // namespace

int EuclideanClusterer::findRoot(int c) {
  while (parent_[static_cast<std::size_t>(c)] != c) {
    auto& p = parent_[static_cast<std::size_t>(c)];
    p = parent_[static_cast<std::size_t>(p)];  // path halving
    c = p;
  }
  return c;
}

void EuclideanClusterer::sortByKey() {
  // (key, index) pairs are appended in index order, so a stable sort by key alone gives the
  // order of std::sort on the pairs. Least significant digit first, 8 bits a pass: a frame's
  // keys need about three passes over about a thousand points.
  int64_t max_key = 0;
  for (const auto& e : sorted_) max_key = std::max(max_key, e.first);
  int passes = 0;
  while (passes < 8 && (max_key >> (8 * passes)) != 0) ++passes;
  if (passes > 4 || sorted_.size() < 64) {  // wide keys or few points: a comparison sort is as quick
    std::sort(sorted_.begin(), sorted_.end());
    return;
  }
  radix_tmp_.resize(sorted_.size());
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = 8 * pass;
    std::size_t count[257] = {0};
    for (const auto& e : sorted_) ++count[std::size_t((e.first >> shift) & 0xFF) + 1];
    for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
    for (const auto& e : sorted_) radix_tmp_[count[std::size_t((e.first >> shift) & 0xFF)]++] = e;
    sorted_.swap(radix_tmp_);
  }
}

std::vector<std::vector<int>> EuclideanClusterer::cluster(const std::vector<Eigen::Vector3f>& points,
                                                          double tolerance, int min_points, int max_points) {
  std::vector<std::vector<int>> out;
  const std::size_t n = points.size();
  if (n == 0 || !(tolerance > 0.0) || !std::isfinite(tolerance)) return out;

  // Cells of edge s < tolerance / sqrt(3): any two points of a cell are closer than the
  // tolerance (a small margin keeps that true after float rounding).
  const double s = tolerance / std::sqrt(3.0) * (1.0 - 1e-3);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  if (!(lo.x() <= hi.x())) return out;  // no finite point
  const Eigen::Vector3d extent = (hi - lo) / s;
  if (!(extent.maxCoeff() < 1e6))
    throw std::invalid_argument("EuclideanClusterer: points span more than 1e6 cells of tolerance/sqrt(3) per axis");
  // Cell coordinates are padded by `reach` cells on every side, so that a neighbour's key is
  // plain key arithmetic with no bounds check (the padding holds no point).
  const int reach = int(std::ceil(tolerance / s));
  const int64_t nx = int64_t(extent.x()) + 1 + 2 * reach, ny = int64_t(extent.y()) + 1 + 2 * reach,
                nz = int64_t(extent.z()) + 1 + 2 * reach;
  const double inv_s = 1.0 / s;
  const auto axis = [&](float v, double v0, int64_t cells_on_axis) {
    return std::min<int64_t>(cells_on_axis - 1 - reach, int64_t((double(v) - v0) * inv_s) + reach);
  };

  sorted_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = points[i];
    if (!p.allFinite()) continue;
    const int64_t key = (axis(p.x(), lo.x(), nx) * ny + axis(p.y(), lo.y(), ny)) * nz + axis(p.z(), lo.z(), nz);
    sorted_.emplace_back(key, static_cast<int>(i));
  }
  sortByKey();
  cell_begin_.clear();
  cell_key_.clear();
  for (std::size_t k = 0; k < sorted_.size(); ++k) {
    if (cell_key_.empty() || cell_key_.back() != sorted_[k].first) {
      cell_key_.push_back(sorted_[k].first);
      cell_begin_.push_back(static_cast<int>(k));
    }
  }
  const int cells = static_cast<int>(cell_key_.size());
  cell_begin_.push_back(static_cast<int>(sorted_.size()));
  parent_.resize(std::size_t(cells));
  for (int c = 0; c < cells; ++c) parent_[std::size_t(c)] = c;

  // Cells are sorted by key, i.e. by column (x, y) and then z: a column's cells are a run
  // of the list. A neighbour column is found through a 2-D table of run starts (small enough
  // to stay in cache, unlike a 3-D grid), then its few cells are scanned for z.
  const int64_t columns = nx * ny;
  const bool dense = columns <= kDenseLimit;
  if (dense && col_begin_.size() < std::size_t(columns)) col_begin_.assign(std::size_t(columns), -1);
  cell_col_.resize(std::size_t(cells));
  cell_z_.resize(std::size_t(cells));
  for (int c = 0; c < cells; ++c) {
    cell_col_[std::size_t(c)] = cell_key_[std::size_t(c)] / nz;
    cell_z_[std::size_t(c)] = int(cell_key_[std::size_t(c)] % nz);
  }
  if (dense)
    for (int c = cells - 1; c >= 0; --c) col_begin_[std::size_t(cell_col_[std::size_t(c)])] = c;  // first cell wins
  const auto columnStart = [&](int64_t col) -> int {
    if (dense) return col_begin_[std::size_t(col)];
    const int c = int(std::lower_bound(cell_col_.begin(), cell_col_.end(), col) - cell_col_.begin());
    return c < cells && cell_col_[std::size_t(c)] == col ? c : -1;
  };

  // Neighbour columns (dx, dy) that can hold a point closer than the tolerance, each column
  // pair once (dx > 0, or dx == 0 and dy >= 0), with the largest |dz| that still can.
  const auto gap = [](int d) { return double(std::max(std::abs(d) - 1, 0)); };
  col_offsets_.clear();
  for (int dx = 0; dx <= reach; ++dx)
    for (int dy = -reach; dy <= reach; ++dy) {
      if (dx == 0 && dy < 0) continue;
      int dz_max = -1;
      for (int dz = 0; dz <= reach; ++dz) {
        const double g2 = (gap(dx) * gap(dx) + gap(dy) * gap(dy) + gap(dz) * gap(dz)) * s * s;
        if (g2 < tolerance * tolerance) dz_max = dz;
      }
      if (dz_max >= 0) col_offsets_.push_back({dx * ny + dy, dz_max});
    }

  const auto r2 = static_cast<float>(tolerance * tolerance);
  const auto close = [&](int a, int b) {
    const auto& p = points[std::size_t(a)];
    const auto& q = points[std::size_t(b)];
    const float dx = p.x() - q.x(), dy = p.y() - q.y(), dz = p.z() - q.z();
    return dx * dx + dy * dy + dz * dz < r2;
  };
  const auto link = [&](int c, int d) {
    const int rc = findRoot(c), rd = findRoot(d);
    if (rc == rd) return;
    bool linked = false;
    for (int a = cell_begin_[std::size_t(c)]; a < cell_begin_[std::size_t(c) + 1] && !linked; ++a)
      for (int b = cell_begin_[std::size_t(d)]; b < cell_begin_[std::size_t(d) + 1] && !linked; ++b)
        linked = close(sorted_[std::size_t(a)].second, sorted_[std::size_t(b)].second);
    if (linked) parent_[std::size_t(rc)] = rd;
  };
  for (int c = 0; c < cells; ++c) {
    const int64_t col = cell_col_[std::size_t(c)];
    const int z = cell_z_[std::size_t(c)];
    for (const ColumnOffset& o : col_offsets_) {
      if (o.d == 0) {
        // Own column: the cells above this one (those below linked to it already).
        for (int d = c + 1; d < cells && cell_col_[std::size_t(d)] == col; ++d) {
          if (cell_z_[std::size_t(d)] - z > o.dz_max) break;
          link(c, d);
        }
        continue;
      }
      const int64_t ncol = col + o.d;
      for (int d = columnStart(ncol); d >= 0 && d < cells && cell_col_[std::size_t(d)] == ncol; ++d) {
        const int dz = cell_z_[std::size_t(d)] - z;
        if (dz < -o.dz_max) continue;
        if (dz > o.dz_max) break;
        link(c, d);
      }
    }
  }
  if (dense)
    for (int c = 0; c < cells; ++c) col_begin_[std::size_t(cell_col_[std::size_t(c)])] = -1;

  // Groups in order of their lowest point index; each group's indices ascending.
  group_of_root_.assign(std::size_t(cells), -1);
  cell_of_point_.assign(n, -1);
  for (int c = 0; c < cells; ++c)
    for (int k = cell_begin_[std::size_t(c)]; k < cell_begin_[std::size_t(c) + 1]; ++k)
      cell_of_point_[std::size_t(sorted_[std::size_t(k)].second)] = c;
  std::vector<std::vector<int>> groups;
  for (std::size_t i = 0; i < n; ++i) {
    if (cell_of_point_[i] < 0) continue;
    int& g = group_of_root_[std::size_t(findRoot(cell_of_point_[i]))];
    if (g < 0) {
      g = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    groups[std::size_t(g)].push_back(static_cast<int>(i));
  }
  for (auto& g : groups) {
    const auto size = static_cast<int64_t>(g.size());
    if (size >= min_points && size <= max_points) out.push_back(std::move(g));
  }
  return out;
}

}  // namespace perception
}  // namespace ucon
