#include "ucon/world/scenario.hpp"

#include <cmath>
#include <set>
#include <sstream>

namespace ucon {
namespace world {

namespace {

bool finite2(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

std::string idx(const char* what, std::size_t i) {
  std::ostringstream os;
  os << what << "[" << i << "]";
  return os.str();
}

}  // namespace

std::optional<std::string> validate(const Scenario& s) {
  const Bounds& b = s.bounds;
  if (!(std::isfinite(b.xmin) && std::isfinite(b.xmax) && std::isfinite(b.ymin) &&
        std::isfinite(b.ymax)) ||
      !(b.xmax > b.xmin) || !(b.ymax > b.ymin))
    return std::string("bounds: need finite xmin < xmax and ymin < ymax");
  if (!(s.duration_s > 0.0) || !std::isfinite(s.duration_s)) return std::string("duration: must be > 0");
  const RobotSpec& r = s.robot;
  if (!finite2(r.start) || !std::isfinite(r.start_yaw)) return std::string("robot.start: not finite");
  if (!(r.radius > 0.0 && r.radius < 10.0)) return std::string("robot.radius: must be in (0, 10)");
  if (!(r.max_speed > 0.0 && r.max_speed < 100.0)) return std::string("robot.max_speed: must be in (0, 100)");
  if (!(r.max_accel > 0.0 && r.max_accel < 100.0)) return std::string("robot.max_accel: must be in (0, 100)");
  for (std::size_t i = 0; i < r.goals.size(); ++i)
    if (!finite2(r.goals[i])) return idx("robot.goals", i) + ": not finite";

  for (std::size_t i = 0; i < s.statics.size(); ++i) {
    const StaticObstacle& o = s.statics[i];
    const std::string n = idx("static", i);
    if (!finite2(o.center)) return n + ".center: not finite";
    if (!(o.height > 0.0 && o.height < 1000.0)) return n + ".height: must be in (0, 1000)";
    if (!(o.reflectivity >= 0.0 && o.reflectivity <= 255.0)) return n + ".reflectivity: must be in [0, 255]";
    if (o.kind == ShapeKind::kCylinder) {
      if (!(o.radius > 0.0 && o.radius < 1000.0)) return n + ".radius: must be in (0, 1000)";
    } else {
      if (!(o.half_size.x() > 0.0 && o.half_size.y() > 0.0 && finite2(o.half_size)))
        return n + ".size: both sides must be > 0";
      if (!std::isfinite(o.yaw)) return n + ".yaw: not finite";
    }
  }

  std::set<int64_t> ids;
  for (std::size_t i = 0; i < s.movers.size(); ++i) {
    const MovingObstacle& m = s.movers[i];
    const std::string n = idx("moving", i);
    if (m.id <= 0) return n + ".id: must be > 0";
    if (!ids.insert(m.id).second) return n + ".id: duplicate id " + std::to_string(m.id);
    if (!(m.radius > 0.0 && m.radius < 100.0)) return n + ".radius: must be in (0, 100)";
    if (!(m.height > 0.0 && m.height < 1000.0)) return n + ".height: must be in (0, 1000)";
    if (!(m.reflectivity >= 0.0 && m.reflectivity <= 255.0)) return n + ".reflectivity: must be in [0, 255]";
    if (2.0 * m.radius >= (b.xmax - b.xmin) || 2.0 * m.radius >= (b.ymax - b.ymin))
      return n + ".radius: does not fit in the bounds";
    const MotionParams& p = m.motion;
    const std::string mn = n + ".motion";
    switch (p.kind) {
      case MotionKind::kConstantAcceleration:
        if (!finite2(p.acceleration)) return mn + ".acceleration: not finite";
        if (!(p.speed_cap > 0.0 && std::isfinite(p.speed_cap))) return mn + ".speed_cap: must be > 0";
        if (p.velocity.norm() > p.speed_cap + 1e-9) return mn + ".velocity: faster than speed_cap";
        [[fallthrough]];
      case MotionKind::kConstantVelocity:
        if (!finite2(p.position)) return mn + ".position: not finite";
        if (!finite2(p.velocity)) return mn + ".velocity: not finite";
        break;
      case MotionKind::kSinusoidal:
        if (!finite2(p.position)) return mn + ".position: not finite";
        if (!finite2(p.amplitude) || !finite2(p.phase) || !finite2(p.offset))
          return mn + ": amplitude, phase and offset must be finite";
        if (!(p.omega.x() > 0.0 && p.omega.y() > 0.0 && finite2(p.omega)))
          return mn + ".omega: both must be > 0";
        break;
      case MotionKind::kPedestrian: {
        if (p.waypoints.size() < 2) return mn + ".waypoints: need at least 2";
        for (std::size_t k = 0; k < p.waypoints.size(); ++k) {
          const Vec2& w = p.waypoints[k];
          if (!finite2(w)) return mn + idx(".waypoints", k) + ": not finite";
          if (w.x() < b.xmin || w.x() > b.xmax || w.y() < b.ymin || w.y() > b.ymax)
            return mn + idx(".waypoints", k) + ": outside the bounds";
        }
        if (!(p.speed_min > 0.0 && p.speed_max >= p.speed_min && p.speed_max < 100.0))
          return mn + ".speed: need 0 < min <= max < 100";
        if (!(p.speed_change_min_s > 0.0 && p.speed_change_max_s >= p.speed_change_min_s &&
              std::isfinite(p.speed_change_max_s)))
          return mn + ".speed_change_interval: need 0 < min <= max";
        if (!(p.pause_probability >= 0.0 && p.pause_probability <= 1.0))
          return mn + ".pause_probability: must be in [0, 1]";
        if (!(p.pause_min_s >= 0.0 && p.pause_max_s >= p.pause_min_s && std::isfinite(p.pause_max_s)))
          return mn + ".pause: need 0 <= min <= max";
        if (!(p.jitter >= 0.0 && std::isfinite(p.jitter))) return mn + ".jitter: must be >= 0";
        break;
      }
    }
  }
  return std::nullopt;
}

StaticObstacle makeWall(const Vec2& a, const Vec2& b, double thickness, double height) {
  StaticObstacle o;
  o.kind = ShapeKind::kBox;
  o.center = 0.5 * (a + b);
  const Vec2 d = b - a;
  o.half_size = Vec2(0.5 * d.norm(), 0.5 * thickness);
  o.yaw = std::atan2(d.y(), d.x());
  o.height = height;
  return o;
}

}  // namespace world
}  // namespace ucon
