#include "ucon/perception/proximity_index.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ucon {
namespace perception {

namespace {
constexpr double kCell = 0.25;              ///< preferred cell edge [m]: about the motion test's radius
constexpr int64_t kMaxCells = int64_t(1) << 22;  ///< a larger extent gets larger cells
}  // namespace

/// A dense grid of cells over the points' bounding box, the points stored cell by cell
/// (counting sort, z fastest: a column of cells is one contiguous run of points). Building is
/// linear in the points; a query visits the columns the ball's box touches and stops at the
/// first point inside the ball.
struct ProximityIndex::Impl {
  std::vector<Eigen::Vector3f> pts;  ///< finite points, ordered by cell
  std::vector<uint32_t> start;       ///< per cell: first index into pts; one extra entry at the end
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  double cell = kCell, inv_cell = 1.0 / kCell;
  int64_t nx = 0, ny = 0, nz = 0;
  int64_t axis(double v, double v0, int64_t n) const {
    return std::clamp<int64_t>(int64_t(std::floor((v - v0) * inv_cell)), 0, n - 1);
  }
};

ProximityIndex::ProximityIndex() : impl_(std::make_unique<Impl>()) {}
ProximityIndex::~ProximityIndex() = default;
ProximityIndex::ProximityIndex(ProximityIndex&&) noexcept = default;
ProximityIndex& ProximityIndex::operator=(ProximityIndex&&) noexcept = default;

void ProximityIndex::build(const std::vector<Eigen::Vector3f>& points) {
  Impl& m = *impl_;
  m.pts.clear();
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
  // Cells of kCell, grown (exactness does not depend on the size) until the grid is bounded.
  m.lo = lo;
  m.cell = kCell;
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
  // Scatter with start[c] as the fill position of cell c (it ends at the next cell's start),
  // then shift the starts back by one cell: no second array.
  for (const auto& p : points)
    if (p.allFinite()) m.pts[m.start[std::size_t(cellOf(p))]++] = p;
  for (std::size_t c = m.start.size() - 1; c > 0; --c) m.start[c] = m.start[c - 1];
  m.start[0] = 0;
}

int ProximityIndex::size() const { return static_cast<int>(impl_->pts.size()); }

bool ProximityIndex::anyWithin(const Eigen::Vector3f& q, float max_dist2) const {
  const Impl& m = *impl_;
  if (m.pts.empty() || !q.allFinite() || !std::isfinite(max_dist2) || max_dist2 < 0.0f) return false;
  // The cells the ball's box touches (a hair wider: the test below is the exact one).
  const double r = std::sqrt(double(max_dist2)) * (1.0 + 1e-6) + 1e-6;
  const Eigen::Vector3d qd = q.cast<double>();
  const Eigen::Vector3d a = (qd.array() - r - m.lo.array()) * m.inv_cell;
  const Eigen::Vector3d b = (qd.array() + r - m.lo.array()) * m.inv_cell;
  const Eigen::Vector3d n(double(m.nx), double(m.ny), double(m.nz));
  if ((b.array() < 0.0).any() || (a.array() >= n.array()).any()) return false;  // ball outside the grid
  const auto range = [](double v0, double v1, int64_t cells, int64_t* i0, int64_t* i1) {
    *i0 = std::max<int64_t>(0, int64_t(std::floor(v0)));
    *i1 = std::min<int64_t>(cells - 1, int64_t(std::floor(v1)));
  };
  int64_t x0, x1, y0, y1, z0, z1;
  range(a.x(), b.x(), m.nx, &x0, &x1);
  range(a.y(), b.y(), m.ny, &y0, &y1);
  range(a.z(), b.z(), m.nz, &z0, &z1);
  for (int64_t x = x0; x <= x1; ++x)
    for (int64_t y = y0; y <= y1; ++y) {
      const int64_t col = (x * m.ny + y) * m.nz;
      const uint32_t end = m.start[std::size_t(col + z1) + 1];
      for (uint32_t i = m.start[std::size_t(col + z0)]; i < end; ++i) {
        const Eigen::Vector3f& p = m.pts[i];
        const float dx = p.x() - q.x(), dy = p.y() - q.y(), dz = p.z() - q.z();
        if (dx * dx + dy * dy + dz * dz <= max_dist2) return true;
      }
    }
  return false;
}

}  // namespace perception
}  // namespace ucon
