#include "ucon/perception/static_persistence.hpp"

#include <cmath>
#include <stdexcept>

namespace ucon {
namespace perception {

StaticPersistence::StaticPersistence(double cell, double persistence, double max_gap, int cells_per_side)
    : cells_(cell, max_gap, cells_per_side),
      persistence_us_(static_cast<int64_t>(std::llround(persistence * 1e6))),
      live_index_(static_cast<std::size_t>(cells_per_side) * static_cast<std::size_t>(cells_per_side), -1) {
  if (!(persistence >= 0.0)) throw std::invalid_argument("StaticPersistence: persistence must be >= 0");
}

void StaticPersistence::reset() {
  cells_.reset();
  last_utime_ = INT64_MIN;
  for (const Live& l : live_) live_index_[static_cast<std::size_t>(l.slot)] = -1;
  live_.clear();
}

void StaticPersistence::update(int64_t utime, const std::vector<Eigen::Vector3f>& points,
                               std::vector<char>* persistent, const Occlusion* occlusion,
                               const std::vector<char>* tracked) {
  if (utime < last_utime_) reset();
  last_utime_ = utime;
  persistent->assign(points.size(), 0);
  point_slot_.assign(points.size(), -1);
  // First record the hits of the whole frame, then judge: every point of a cell gets the
  // same answer.
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int s = cells_.hit(utime, static_cast<double>(points[i].x()), static_cast<double>(points[i].y()));
    point_slot_[i] = s;
    if (s < 0 || occlusion == nullptr) continue;
    const bool on_track = tracked != nullptr && i < tracked->size() && (*tracked)[i] != 0;
    int& k = live_index_[static_cast<std::size_t>(s)];
    if (k < 0) {
      k = static_cast<int>(live_.size());
      live_.push_back({s, cells_.slotKey(s), points[i], utime, on_track});
    } else {
      Live& l = live_[static_cast<std::size_t>(k)];
      l.tracked = l.hit_utime == utime ? l.tracked && on_track : on_track;
      l.key = cells_.slotKey(s);
      l.point = points[i];
      l.hit_utime = utime;
    }
  }
  if (occlusion != nullptr && occlusion->grid != nullptr && occlusion->nearest != nullptr)
    holdHidden(utime, *occlusion);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_slot_[i] < 0) continue;
    (*persistent)[i] = utime - cells_.slotSince(point_slot_[i]) >= persistence_us_ ? 1 : 0;
  }
}

void StaticPersistence::holdHidden(int64_t utime, const Occlusion& o) {
  const std::vector<float>& nearest = *o.nearest;
  for (std::size_t k = 0; k < live_.size();) {
    Live& l = live_[k];
    if (!cells_.running(l.slot, l.key, utime)) {
      // The run ended (or another cell took the slot): forget the entry.
      live_index_[static_cast<std::size_t>(l.slot)] = -1;
      if (k + 1 != live_.size()) {
        live_[k] = live_.back();
        live_index_[static_cast<std::size_t>(live_[k].slot)] = static_cast<int>(k);
      }
      live_.pop_back();
      continue;
    }
    if (cells_.slotLast(l.slot) < utime && !l.tracked && static_cast<double>(utime - l.hit_utime) <= o.max_hidden * 1e6 &&
        (l.point.head<2>() - o.origin.head<2>()).squaredNorm() <= o.max_range * o.max_range) {
      const Eigen::Vector3f ray = l.point - o.origin;
      const float range = ray.norm();
      const auto bin = static_cast<std::size_t>(o.grid->bin(ray));
      if (range > 0.0f && bin < nearest.size() && nearest[bin] < range - o.margin && cells_.hold(l.slot, l.key, utime))
        ++holds_;
    }
    ++k;
  }
}

}  // namespace perception
}  // namespace ucon
