#include "ucon/perception/free_space_memory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ucon/fast_atan2.hpp"
#include "ucon/perception/preprocess.hpp"

namespace ucon {
namespace perception {

int FreeSpaceMemory::sideFor(const Params& params) {
  // Twice the followed range plus what the robot drives within the horizon, at most 2048 cells
  // (100 MB of slots); a smaller grid only forgets (slots are keyed by their cell).
  const double span = 2.0 * (params.range + 5.0) / std::max(params.cell, 1e-3);
  int side = 2;
  while (side < 2048 && side < span) side *= 2;
  return side;
}

FreeSpaceMemory::FreeSpaceMemory(const Params& params) : FreeSpaceMemory(params, sideFor(params)) {}

FreeSpaceMemory::FreeSpaceMemory(const Params& params, int cells_per_side)
    : params_(params),
      horizon_us_(static_cast<int64_t>(std::llround(params.horizon * 1e6))),
      period_us_(static_cast<int64_t>(std::llround(params.period * 1e6))),
      inv_cell_(static_cast<float>(1.0 / params.cell)),
      side_(cells_per_side),
      mask_(cells_per_side - 1) {
  if (!(params.horizon >= 0.0) || !(params.cell > 0.0) || !(params.max_height > params.min_height) ||
      !(params.range >= 0.0) || !(params.margin >= 0.0) || !(params.period >= 0.0))
    throw std::invalid_argument("FreeSpaceMemory: bad parameters");
  if (cells_per_side < 2 || (cells_per_side & (cells_per_side - 1)) != 0)
    throw std::invalid_argument("FreeSpaceMemory: cells_per_side must be a power of two >= 2");
  if (enabled()) reset();
}

void FreeSpaceMemory::reset() {
  slots_.assign(static_cast<std::size_t>(side_) * static_cast<std::size_t>(side_), Slot{});
  last_utime_ = INT64_MIN;
}

namespace {
/// Cell index of a coordinate; false for a non-finite or absurdly far one.
bool cellOf(float v, float inv_cell, int64_t* i) {
  const float f = std::floor(v * inv_cell);
  if (!std::isfinite(f) || std::abs(f) > 1e9f) return false;
  *i = static_cast<int64_t>(f);
  return true;
}

/// Packed key of cell (ix, iy). Shifted as unsigned: left-shifting a negative signed value is
/// undefined in C++17.
int64_t keyOf(int64_t ix, int64_t iy) {
  return static_cast<int64_t>((static_cast<uint64_t>(ix) << 32) ^ (static_cast<uint64_t>(iy) & 0xffffffffULL));
}
}  // namespace

const FreeSpaceMemory::Slot* FreeSpaceMemory::find(int64_t ix, int64_t iy) const {
  const Slot& slot = slots_[slotIndex(ix, iy)];
  return slot.key == keyOf(ix, iy) ? &slot : nullptr;
}

FreeSpaceMemory::Slot* FreeSpaceMemory::claim(float x, float y) {
  int64_t ix = 0, iy = 0;
  if (!cellOf(x, inv_cell_, &ix) || !cellOf(y, inv_cell_, &iy)) return nullptr;
  Slot& slot = slots_[slotIndex(ix, iy)];
  const int64_t key = keyOf(ix, iy);
  if (slot.key != key) slot = Slot{key, INT64_MIN, INT64_MIN};
  return &slot;
}

void FreeSpaceMemory::walk(const Eigen::Vector3f& o, const Eigen::Vector2f& u, float from, float to, int64_t utime) {
  const float step = static_cast<float>(0.5 * params_.cell);
  for (float s = from; s <= to; s += step) {
    Slot* slot = claim(o.x() + u.x() * s, o.y() + u.y() * s);
    // A cell that held a return within the horizon is not seen free: a ray passing beside a
    // surface crosses the surface's cell, and a sparse scan does not sample every surface
    // cell in every frame.
    if (slot && (slot->hit_utime == INT64_MIN || utime - slot->hit_utime > horizon_us_)) slot->free_utime = utime;
  }
}

void FreeSpaceMemory::mark(const Frame& frame) {
  if (!enabled()) return;
  const int64_t t = frame.utime;
  if (t < last_utime_) reset();
  // Once per period: a memory kept for seconds gains little from every 20 ms frame.
  if (last_utime_ != INT64_MIN && t - last_utime_ < period_us_) return;
  last_utime_ = t;
  // The cells holding a return of this frame first: rays crossing them passed beside it.
  for (const auto& p : frame.points)
    if (Slot* slot = claim(p.x(), p.y())) slot->hit_utime = t;
  // Each return's ray is free in the band from the sensor out to where it leaves the band, or
  // to `margin` before its return, or to `range`. Rays of one narrow azimuth bin are nearly
  // collinear: the bin is followed once, along its centre, as far as its farthest such extent
  // (the union of the rays' free stretches; a frame has several returns per bin).
  const Eigen::Vector3f o = frame.sensor_origin;
  const float floor_z = static_cast<float>(frame.pose.translation().z());
  const float lo = static_cast<float>(params_.min_height), hi = static_cast<float>(params_.max_height);
  const float h0 = o.z() - floor_z;
  const float range = static_cast<float>(params_.range), margin = static_cast<float>(params_.margin);
  extent_.assign(kAzimuthBins, 0.0f);
  for (const auto& q : frame.returns) {
    const Eigen::Vector2f d = q.head<2>() - o.head<2>();
    const float D = d.norm();
    if (!(D > 1e-3f) || !std::isfinite(D)) continue;
    const float end = std::min(D - margin, range);
    if (!(end > 0.0f)) continue;
    // The ray's height above the floor at x-y distance s from the sensor: h0 + slope s. Its
    // free stretch in the band is [a, b]; a = 0 when the sensor is in the band.
    const float slope = (q.z() - o.z()) / D;
    float a = 0.0f, b = end;
    if (std::abs(slope) < 1e-6f) {
      if (h0 < lo || h0 > hi) continue;
    } else {
      const float s1 = (lo - h0) / slope, s2 = (hi - h0) / slope;
      a = std::max(a, std::min(s1, s2));
      b = std::min(b, std::max(s1, s2));
      if (!(a < b)) continue;
    }
    if (a > 0.0f) {
      // A sensor mounted above (or below) the band: the stretch starts away from the sensor,
      // and stretches of one bin need not overlap; this ray is followed on its own.
      walk(o, d / D, a, b, t);
      continue;
    }
    const double az = fastAtan2(static_cast<double>(d.y()), static_cast<double>(d.x())) + M_PI;
    const auto bin = std::min<std::size_t>(static_cast<std::size_t>(az * (kAzimuthBins / (2.0 * M_PI))), kAzimuthBins - 1);
    extent_[bin] = std::max(extent_[bin], b);
  }
  for (std::size_t k = 0; k < kAzimuthBins; ++k) {
    if (!(extent_[k] > 0.0f)) continue;
    const double az = (static_cast<double>(k) + 0.5) * (2.0 * M_PI / kAzimuthBins) - M_PI;
    walk(o, Eigen::Vector2f(static_cast<float>(std::cos(az)), static_cast<float>(std::sin(az))), 0.0f, extent_[k], t);
  }
}

bool FreeSpaceMemory::seenFree(const Eigen::Vector3f& p, int64_t now) const {
  if (!enabled()) return false;
  int64_t ix = 0, iy = 0;
  if (!cellOf(p.x(), inv_cell_, &ix) || !cellOf(p.y(), inv_cell_, &iy)) return false;
  for (int64_t dy = -1; dy <= 1; ++dy) {
    for (int64_t dx = -1; dx <= 1; ++dx) {
      const Slot* slot = find(ix + dx, iy + dy);
      if (!slot || slot->free_utime == INT64_MIN || slot->free_utime >= now || now - slot->free_utime > horizon_us_)
        return false;
    }
  }
  return true;
}

}  // namespace perception
}  // namespace ucon
