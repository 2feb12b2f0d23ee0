#include "ucon/perception/static_persistence.hpp"

#include <cmath>
#include <stdexcept>

namespace ucon {
namespace perception {

StaticPersistence::StaticPersistence(double cell, double persistence, double max_gap, int cells_per_side)
    : cells_(cell, max_gap, cells_per_side), persistence_us_(static_cast<int64_t>(std::llround(persistence * 1e6))) {
  if (!(persistence >= 0.0)) throw std::invalid_argument("StaticPersistence: persistence must be >= 0");
}

void StaticPersistence::reset() {
  cells_.reset();
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
  for (std::size_t i = 0; i < points.size(); ++i)
    point_slot_[i] = cells_.hit(utime, static_cast<double>(points[i].x()), static_cast<double>(points[i].y()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_slot_[i] < 0) continue;
    (*persistent)[i] = utime - cells_.slotSince(point_slot_[i]) >= persistence_us_ ? 1 : 0;
  }
}

}  // namespace perception
}  // namespace ucon
