#include "ucon/perception/proximity_index.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ucon {
namespace perception {

namespace {
constexpr int64_t kMaxCells = int64_t(1) << 22;  ///< a larger extent gets larger cells
}  // namespace

/// A dense grid of cells over the points' bounding box, the points stored cell by cell
/// (counting sort, z fastest: a column of cells is one contiguous run of points). Building is
/// linear in the points; a query visits the columns the ball's box touches (anyWithin stops
/// at the first point inside the ball).
struct ProximityIndex::Impl {
  std::vector<Eigen::Vector3f> pts;  ///< finite points, ordered by cell
  std::vector<uint32_t> source;      ///< per entry of pts: its index in the vector given to build()
  std::vector<uint32_t> start;       ///< per cell: first index into pts; one extra entry at the end
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  double cell = 0.25, inv_cell = 4.0;
  int64_t nx = 0, ny = 0, nz = 0;
  int64_t axis(double v, double v0, int64_t n) const {
    return std::clamp<int64_t>(int64_t(std::floor((v - v0) * inv_cell)), 0, n - 1);
  }
  /// The cell ranges of the box around the ball (q, r), a hair wider (the distance tests are
  /// the exact ones); false when the box misses the grid.
  bool ballCells(const Eigen::Vector3f& q, float max_dist2, int64_t lo_idx[3], int64_t hi_idx[3]) const {
    const double r = std::sqrt(double(max_dist2)) * (1.0 + 1e-6) + 1e-6;
    const Eigen::Vector3d qd = q.cast<double>();
    const Eigen::Vector3d a = (qd.array() - r - lo.array()) * inv_cell;
    const Eigen::Vector3d b = (qd.array() + r - lo.array()) * inv_cell;
    const int64_t n[3] = {nx, ny, nz};
    for (int k = 0; k < 3; ++k) {
      if (b[k] < 0.0 || a[k] >= double(n[k])) return false;  // ball outside the grid
      lo_idx[k] = std::max<int64_t>(0, int64_t(std::floor(a[k])));
      hi_idx[k] = std::min<int64_t>(n[k] - 1, int64_t(std::floor(b[k])));
    }
    return true;
  }
  /// Calls visit(i) for the entries i of pts in the cells the ball (q, r) touches, column by
  /// column, until it returns true; returns whether it did.
  template <class Visit>
  bool visitBall(const Eigen::Vector3f& q, float max_dist2, Visit&& visit) const {
    int64_t lo_idx[3], hi_idx[3];
    if (!ballCells(q, max_dist2, lo_idx, hi_idx)) return false;
    for (int64_t x = lo_idx[0]; x <= hi_idx[0]; ++x)
      for (int64_t y = lo_idx[1]; y <= hi_idx[1]; ++y) {
        const int64_t col = (x * ny + y) * nz;
        const uint32_t end = start[std::size_t(col + hi_idx[2]) + 1];
        for (uint32_t i = start[std::size_t(col + lo_idx[2])]; i < end; ++i)
          if (visit(i)) return true;
      }
    return false;
  }
};

ProximityIndex::ProximityIndex() : impl_(std::make_unique<Impl>()) {}
ProximityIndex::~ProximityIndex() = default;
ProximityIndex::ProximityIndex(ProximityIndex&&) noexcept = default;
ProximityIndex& ProximityIndex::operator=(ProximityIndex&&) noexcept = default;

void ProximityIndex::build(const std::vector<Eigen::Vector3f>& points, double cell) {
  Impl& m = *impl_;
  m.pts.clear();
  m.source.clear();
  m.start.clear();
  m.nx = m.ny = m.nz = 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  std::size_t finite = 0;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    ++finite;
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  if (finite == 0) return;
  // Cells of `cell`, grown (exactness does not depend on the size) until the grid is bounded.
  m.lo = lo;
  m.cell = std::isfinite(cell) && cell > 0.0 ? cell : 0.25;
  for (;;) {
    const Eigen::Vector3d n = ((hi - lo) / m.cell).array().floor() + 1.0;
    if (n.prod() <= double(kMaxCells)) {
      m.nx = int64_t(n.x()), m.ny = int64_t(n.y()), m.nz = int64_t(n.z());
      break;
    }
    m.cell *= 2.0;
  }
  m.inv_cell = 1.0 / m.cell;
  const auto cellOf = [&](const Eigen::Vector3f& p) {
    return (m.axis(p.x(), m.lo.x(), m.nx) * m.ny + m.axis(p.y(), m.lo.y(), m.ny)) * m.nz + m.axis(p.z(), m.lo.z(), m.nz);
  };
  m.start.assign(std::size_t(m.nx * m.ny * m.nz) + 1, 0);
  for (const auto& p : points)
    if (p.allFinite()) ++m.start[std::size_t(cellOf(p)) + 1];
  for (std::size_t c = 1; c < m.start.size(); ++c) m.start[c] += m.start[c - 1];
  m.pts.resize(finite);
  m.source.resize(finite);
  // Scatter with start[c] as the fill position of cell c (it ends at the next cell's start),
  // then shift the starts back by one cell: no second array. Within a cell, points keep
  // their order in `points`.
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (!p.allFinite()) continue;
    const uint32_t at = m.start[std::size_t(cellOf(p))]++;
    m.pts[at] = p;
    m.source[at] = uint32_t(i);
  }
  for (std::size_t c = m.start.size() - 1; c > 0; --c) m.start[c] = m.start[c - 1];
  m.start[0] = 0;
}

int ProximityIndex::size() const { return static_cast<int>(impl_->pts.size()); }

bool ProximityIndex::anyWithin(const Eigen::Vector3f& q, float max_dist2) const {
  const Impl& m = *impl_;
  if (m.pts.empty() || !q.allFinite() || !std::isfinite(max_dist2) || max_dist2 < 0.0f) return false;
  return m.visitBall(q, max_dist2, [&](uint32_t i) {
    const Eigen::Vector3f& p = m.pts[i];
    const float dx = p.x() - q.x(), dy = p.y() - q.y(), dz = p.z() - q.z();
    return dx * dx + dy * dy + dz * dz <= max_dist2;  // the first point inside ends the search
  });
}

int ProximityIndex::nearestWithin(const Eigen::Vector3f& q, float max_dist2, float* dist2) const {
  const Impl& m = *impl_;
  if (m.pts.empty() || !q.allFinite() || !std::isfinite(max_dist2) || !(max_dist2 > 0.0f)) return -1;
  // The squared distance as a KD-tree's L2 metric sums it: ((dx^2) + dy^2) + dz^2 in float.
  float best = max_dist2;
  int64_t best_i = -1;
  m.visitBall(q, max_dist2, [&](uint32_t i) {
    const Eigen::Vector3f& p = m.pts[i];
    const float dx = q.x() - p.x(), dy = q.y() - p.y(), dz = q.z() - p.z();
    const float d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < best || (d2 == best && best_i >= 0 && m.source[i] < uint32_t(best_i))) {
      best = d2;
      best_i = m.source[i];
    }
    return false;
  });
  if (best_i >= 0 && dist2) *dist2 = best;
  return int(best_i);
}

}  // namespace perception
}  // namespace ucon
