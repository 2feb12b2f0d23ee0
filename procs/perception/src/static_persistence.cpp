#include "ucon/perception/static_persistence.hpp"

#include <cmath>
#include <stdexcept>

namespace ucon {
namespace perception {

StaticPersistence::StaticPersistence(double cell, double persistence, double max_gap, int cells_per_side)
    : inv_cell_(1.0 / cell),
      persistence_us_(static_cast<int64_t>(std::llround(persistence * 1e6))),
      max_gap_us_(static_cast<int64_t>(std::llround(max_gap * 1e6))),
      side_(cells_per_side),
      mask_(cells_per_side - 1) {
  if (!(cell > 0.0) || !(persistence >= 0.0) || !(max_gap > 0.0))
    throw std::invalid_argument("StaticPersistence: cell and max_gap must be > 0, persistence >= 0");
  if (cells_per_side < 2 || (cells_per_side & (cells_per_side - 1)) != 0)
    throw std::invalid_argument("StaticPersistence: cells_per_side must be a power of two >= 2");
  reset();
}

void StaticPersistence::reset() {
  slots_.assign(static_cast<std::size_t>(side_) * static_cast<std::size_t>(side_), Slot{});
  last_utime_ = INT64_MIN;
}

void StaticPersistence::update(int64_t utime, const std::vector<Eigen::Vector3f>& points,
                               std::vector<char>* persistent) {
  if (utime < last_utime_) reset();
  last_utime_ = utime;
  persistent->assign(points.size(), 0);
  point_slot_.assign(points.size(), -1);
  // First record the hits of the whole frame, then judge: every point of a cell gets the
  // same answer.
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double fx = std::floor(static_cast<double>(points[i].x()) * inv_cell_);
    const double fy = std::floor(static_cast<double>(points[i].y()) * inv_cell_);
    if (!std::isfinite(fx) || !std::isfinite(fy) || std::abs(fx) > 1e9 || std::abs(fy) > 1e9) continue;
    const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
    const int64_t key = (ix << 32) ^ (iy & 0xffffffffLL);
    const int s = static_cast<int>(((iy & mask_) * side_) + (ix & mask_));
    Slot& slot = slots_[static_cast<std::size_t>(s)];
    if (slot.key != key || utime - slot.last_utime > max_gap_us_) {
      slot.key = key;
      slot.first_utime = utime;
    }
    slot.last_utime = utime;
    point_slot_[i] = s;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_slot_[i] < 0) continue;
    const Slot& slot = slots_[static_cast<std::size_t>(point_slot_[i])];
    (*persistent)[i] = utime - slot.first_utime >= persistence_us_ ? 1 : 0;
  }
}

}  // namespace perception
}  // namespace ucon
