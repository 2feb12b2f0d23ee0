#include "ucon/mot/runtime_frames.hpp"

#include <cmath>

#include "ucon/tracked_object_t.hpp"

namespace ucon {
namespace mot {

std::vector<PointXY> groundTruthAt(const sim_ground_truth_t& gt, int64_t utime,
                                   const RuntimeEvalOptions& opt) {
  std::vector<PointXY> out;
  const double dt = static_cast<double>(utime - gt.utime) * 1e-6;
  for (const auto& o : gt.objects) {
    PointXY p{o.id, o.x + o.vx * dt, o.y + o.vy * dt};
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    if (opt.max_range_m > 0.0 &&
        std::hypot(p.x - gt.robot_x, p.y - gt.robot_y) > opt.max_range_m)
      continue;
    out.push_back(p);
  }
  return out;
}

std::vector<PointXY> hypothesesOf(const tracked_objects_t& objects, const RuntimeEvalOptions& opt) {
  std::vector<PointXY> out;
  if (!objects.valid) return out;
  for (const auto& o : objects.objects) {
    const bool take = o.state == tracked_object_t::STATE_CONFIRMED ||
                      (o.state == tracked_object_t::STATE_COASTING && !opt.exclude_coasting) ||
                      (o.state == tracked_object_t::STATE_TENTATIVE && opt.include_tentative);
    if (!take || !std::isfinite(o.x) || !std::isfinite(o.y)) continue;
    out.push_back({o.id, o.x, o.y});
  }
  return out;
}

}  // namespace mot
}  // namespace ucon
