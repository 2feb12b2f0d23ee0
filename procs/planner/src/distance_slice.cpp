#include "distance_slice.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

namespace ucon::planner {

namespace {

/// 1-D squared distance transform (Felzenszwalb & Huttenlocher 2012) of f over n samples,
/// unit spacing, into d. v, z are scratch of size n and n+1.
void distanceTransform1d(const float* f, int n, float* d, int* v, float* z) {
  const float inf = std::numeric_limits<float>::infinity();
  int k = 0;
  int first = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] < inf) {
      first = q;
      break;
    }
  }
  if (first < 0) {
    for (int q = 0; q < n; ++q) d[q] = inf;
    return;
  }
  v[0] = first;
  z[0] = -inf;
  z[1] = inf;
  for (int q = first + 1; q < n; ++q) {
    if (!(f[q] < inf)) continue;
    float s;
    while (true) {
      const int p = v[k];
      s = ((f[q] + float(q) * q) - (f[p] + float(p) * p)) / (2.0f * (q - p));
      if (s <= z[k] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    if (s <= z[k]) {  // k == 0 and the new parabola dominates everywhere
      v[0] = q;
      z[0] = -inf;
      z[1] = inf;
      continue;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = inf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const float dq = float(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

/// An occupied cell's value from the distance `din` [m] between its centre and the nearest
/// free cell's centre (infinite: none): minus that distance less half a cell, capped.
float interiorValue(float din, float half, float cap) { return std::isfinite(din) ? -std::min(cap, din - half) : -cap; }

}  // namespace

DistanceSlice::DistanceSlice(const MapParams& params, LeafCache& leaves)
    : params_(params), leaves_(leaves), flat_(params.resolution) {
  flat_.enableChangeDetection(true);
}

bool DistanceSlice::update(const Eigen::Vector2d& robot_xy, bool force_rebuild) {
  Eigen::Vector2d c = robot_xy.allFinite() ? robot_xy : box_center_;
  bool rebuilt = false;
  project();
  if (!edt_ || force_rebuild || (c - box_center_).cwiseAbs().maxCoeff() >= params_.recenter_distance) {
    rebuild(c);
    rebuilt = true;
  } else {
    edt_->update(true);  // only the cells changed since the last update
    ++incremental_;
  }
  computeSlice(rebuilt);
  return rebuilt;
}

void DistanceSlice::project() {
  octomap::OcTree& tree = leaves_.tree();
  const octomap::key_type band_min = leaves_.bandKeyMin(), band_max = leaves_.bandKeyMax();
  dirty_columns_.clear();
  for (auto it = tree.changedKeysBegin(), end = tree.changedKeysEnd(); it != end; ++it) {
    const octomap::OcTreeKey& k = it->first;
    if (k[2] < band_min || k[2] > band_max) continue;
    dirty_columns_.emplace_back(k[0], k[1]);
  }
  tree.resetChangeDetection();
  std::vector<ColumnKey>& flipped = leaves_.flippedColumns();
  dirty_columns_.insert(dirty_columns_.end(), flipped.begin(), flipped.end());
  flipped.clear();
  std::sort(dirty_columns_.begin(), dirty_columns_.end());
  dirty_columns_.erase(std::unique(dirty_columns_.begin(), dirty_columns_.end()), dirty_columns_.end());
  for (const auto& [kx, ky] : dirty_columns_) {
    bool occ = false;
    for (octomap::key_type kz = band_min; kz <= band_max && !occ; ++kz) {
      float v = 0.0f;
      occ = leaves_.leafValue(octomap::OcTreeKey(kx, ky, kz), &v) && v >= tree.getOccupancyThresLog();
    }
    const octomap::OcTreeKey fk(kx, ky, band_min);
    const auto* existing = flat_.search(fk);
    if (existing ? flat_.isNodeOccupied(existing) == occ : !occ) continue;  // unchanged (unknown = free)
    flat_.setNodeValue(fk, occ ? flat_.getClampingThresMaxLog() : flat_.getClampingThresMinLog());
    flat_changed_.emplace_back(kx, ky);
  }
}

void DistanceSlice::rebuild(const Eigen::Vector2d& c) {
  const double h = params_.box_half_size;
  const float z = float(leaves_.tree().keyToCoord(leaves_.bandKeyMin()));
  const octomap::point3d lo(float(c.x() - h), float(c.y() - h), z);
  const octomap::point3d hi(float(c.x() + h), float(c.y() + h), z);
  edt_.reset();  // free the old grid before allocating the new one
  edt_ = std::make_unique<DynamicEDTOctomap>(float(params_.max_distance), &flat_, lo, hi, false);
  // The constructor read the whole box from the projection: pending changes are in it.
  flat_.resetChangeDetection();
  edt_->update(true);
  key_min_ = flat_.coordToKey(lo);
  key_max_ = flat_.coordToKey(hi);
  box_center_ = c;
  ++rebuilds_;
}

void DistanceSlice::sliceCell(int ix, int iy, float half, float cap) {
  const octomap::OcTreeKey k(key_min_[0] + ix, key_min_[1] + iy, key_min_[2]);
  const float dmin = edt_->getDistance_unsafe(k);
  const std::size_t i = std::size_t(iy) * std::size_t(geometry_.nx) + std::size_t(ix);
  if (dmin <= 0.0f) {
    occupied_[i] = 1;
    values_[i] = 0.0f;
  } else {
    // Distance from this cell centre to the nearest occupied cell's boundary (approx.).
    occupied_[i] = 0;
    values_[i] = std::min(cap, dmin - half);
  }
}

// Fills the 2-D slice from the distance transform. `full` after a rebuild; otherwise only the
// cells near projection cells that changed since the last call: a change moves the distance
// transform only within max_distance of it, and the interior distances only within
// max_distance + half a cell, so every other cell keeps its value (same values as a full
// pass, tested).
void DistanceSlice::computeSlice(bool full) {
  const int nx = key_max_[0] - key_min_[0] + 1;
  const int ny = key_max_[1] - key_min_[1] + 1;
  const double res = leaves_.tree().getResolution();
  const float half = float(0.5 * res);
  const float cap = float(params_.max_distance);
  const std::size_t n = std::size_t(nx) * std::size_t(ny);
  if (full || geometry_.nx != nx || geometry_.ny != ny || values_.size() != n) {
    const octomap::point3d corner = leaves_.tree().keyToCoord(key_min_);
    geometry_.origin = Eigen::Vector2d(corner.x() - 0.5 * res, corner.y() - 0.5 * res);
    geometry_.resolution = res;
    geometry_.nx = nx;
    geometry_.ny = ny;
    values_.assign(n, 0.0f);
    occupied_.assign(n, 0);
    for (int iy = 0; iy < ny; ++iy)
      for (int ix = 0; ix < nx; ++ix) sliceCell(ix, iy, half, cap);
    flat_changed_.clear();
    computeInterior();
    return;
  }
  if (flat_changed_.empty()) return;
  // Cells within r of a change (Chebyshev, in cells) and their bounding box.
  const int r = int(std::ceil((params_.max_distance + res) / res)) + 2;
  dirty_.assign(n, 0);
  int x0 = nx, y0 = ny, x1 = -1, y1 = -1;
  for (const auto& [kx, ky] : flat_changed_) {
    const int cx = int(kx) - int(key_min_[0]), cy = int(ky) - int(key_min_[1]);
    const int ax = std::max(0, cx - r), bx = std::min(nx - 1, cx + r);
    const int ay = std::max(0, cy - r), by = std::min(ny - 1, cy + r);
    if (ax > bx || ay > by) continue;  // outside the box
    for (int iy = ay; iy <= by; ++iy)
      std::fill(dirty_.begin() + std::ptrdiff_t(std::size_t(iy) * nx + ax),
                dirty_.begin() + std::ptrdiff_t(std::size_t(iy) * nx + bx + 1), uint8_t(1));
    x0 = std::min(x0, ax), y0 = std::min(y0, ay), x1 = std::max(x1, bx), y1 = std::max(y1, by);
  }
  flat_changed_.clear();
  if (x1 < 0) return;
  for (int iy = y0; iy <= y1; ++iy)
    for (int ix = x0; ix <= x1; ++ix)
      if (dirty_[std::size_t(iy) * nx + ix]) sliceCell(ix, iy, half, cap);
  // Interior distances of the dirty cells: the nearest free cell by a search outwards.
  interiorNear(x0, y0, x1, y1);
}

// The interior distance of every occupied dirty cell in [x0, x1] x [y0, y1]: the same value
// computeInterior gives (minus the distance to the nearest free cell of the slice, less half
// a cell, capped), found by trying the cells around it nearest first. Obstacles are thin
// shells of surface hits, so a free cell is most often a neighbour. A cell with no free cell
// within R = (cap + half a cell) / resolution + 1 cells gets -cap, as it does there.
void DistanceSlice::interiorNear(int x0, int y0, int x1, int y1) {
  const int nx = geometry_.nx, ny = geometry_.ny;
  const float res = float(geometry_.resolution);
  const float half = 0.5f * res;
  const float cap = float(params_.max_distance);
  const int R = int(std::ceil((params_.max_distance + 0.5 * geometry_.resolution) / geometry_.resolution)) + 1;
  if (R != ring_radius_) {
    ring_.clear();
    for (int dy = -R; dy <= R; ++dy)
      for (int dx = -R; dx <= R; ++dx)
        if (dx * dx + dy * dy <= R * R) ring_.push_back({dx, dy, dx * dx + dy * dy});
    std::stable_sort(ring_.begin(), ring_.end(), [](const RingOffset& a, const RingOffset& b) { return a.d2 < b.d2; });
    ring_radius_ = R;
  }
  for (int iy = y0; iy <= y1; ++iy)
    for (int ix = x0; ix <= x1; ++ix) {
      const std::size_t i = std::size_t(iy) * nx + ix;
      if (!dirty_[i] || !occupied_[i]) continue;
      float v = -cap;
      for (const RingOffset& o : ring_) {
        const int qx = ix + o.dx, qy = iy + o.dy;
        if (qx < 0 || qy < 0 || qx >= nx || qy >= ny || occupied_[std::size_t(qy) * nx + qx]) continue;
        v = interiorValue(std::sqrt(float(o.d2)) * res, half, cap);
        break;
      }
      values_[i] = v;
    }
}

std::size_t DistanceSlice::mismatches() {
  if (!edt_) return 0;
  const std::vector<float> kept_values = values_;
  const std::vector<uint8_t> kept_occupied = occupied_;
  const auto kept_changed = flat_changed_;
  computeSlice(true);
  std::size_t bad = 0;
  for (std::size_t i = 0; i < values_.size(); ++i)
    bad += (values_[i] != kept_values[i] || occupied_[i] != kept_occupied[i]) ? 1 : 0;
  values_ = kept_values;
  occupied_ = kept_occupied;
  flat_changed_ = kept_changed;
  return bad;
}

// Inside obstacles, over the whole slice: minus the distance to the nearest free cell (so the
// optimiser has a gradient that pushes out of an obstacle instead of a flat zero).
void DistanceSlice::computeInterior() {
  const int nx = geometry_.nx, ny = geometry_.ny;
  if (nx <= 0 || ny <= 0) return;
  if (std::find(occupied_.begin(), occupied_.end(), uint8_t(1)) == occupied_.end()) return;
  const float half = float(0.5 * geometry_.resolution);
  const float cap = float(params_.max_distance);
  const float inf = std::numeric_limits<float>::infinity();
  const int m = std::max(nx, ny);
  scratch_f_.resize(std::size_t(nx) * ny);
  scratch_col_.resize(m);
  scratch_d_.resize(m);
  scratch_z_.resize(m + 1);
  scratch_v_.resize(m);
  for (std::size_t i = 0; i < scratch_f_.size(); ++i) scratch_f_[i] = occupied_[i] ? inf : 0.0f;
  // Columns (along y) then rows (along x).
  for (int ix = 0; ix < nx; ++ix) {
    for (int iy = 0; iy < ny; ++iy) scratch_col_[iy] = scratch_f_[std::size_t(iy) * nx + ix];
    distanceTransform1d(scratch_col_.data(), ny, scratch_d_.data(), scratch_v_.data(), scratch_z_.data());
    for (int iy = 0; iy < ny; ++iy) scratch_f_[std::size_t(iy) * nx + ix] = scratch_d_[iy];
  }
  for (int iy = 0; iy < ny; ++iy) {
    float* row = &scratch_f_[std::size_t(iy) * nx];
    distanceTransform1d(row, nx, scratch_d_.data(), scratch_v_.data(), scratch_z_.data());
    for (int ix = 0; ix < nx; ++ix) {
      const std::size_t i = std::size_t(iy) * nx + ix;
      if (occupied_[i]) values_[i] = interiorValue(std::sqrt(scratch_d_[ix]) * float(geometry_.resolution), half, cap);
    }
  }
}

}  // namespace ucon::planner
