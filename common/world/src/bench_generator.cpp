#include "ucon/world/bench_generator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "ucon/world/rng.hpp"

namespace ucon {
namespace world {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// Bounding radius of a static obstacle's footprint (for spacing checks).
double boundRadius(const StaticObstacle& o) {
  return o.kind == ShapeKind::kCylinder ? o.radius : o.half_size.norm();
}

// A unit vector at a uniform random angle, by rejection from the unit disk: only +, *, / and
// sqrt (all correctly rounded under IEEE 754), so the result is the same on every machine,
// unlike cos/sin whose last bit depends on the libm.
Vec2 randomDirection(Rng& rng) {
  while (true) {
    const double x = rng.uniform(-1.0, 1.0), y = rng.uniform(-1.0, 1.0);
    const double r2 = x * x + y * y;
    if (r2 > 1e-6 && r2 <= 1.0) {
      const double r = std::sqrt(r2);
      return Vec2(x / r, y / r);
    }
  }
}

}  // namespace

Scenario generateBench(int num_moving, uint64_t seed, const BenchParams& P) {
  Scenario s;
  s.name = "bench:" + std::to_string(num_moving) + ":" + std::to_string(seed);
  s.seed = seed;
  s.duration_s = P.duration_s;
  s.bounds = Bounds{-P.half_size, P.half_size, -P.half_size, P.half_size};
  Rng rng(deriveSeed(seed, 0xBE4C));

  s.robot.radius = P.robot_radius;
  s.robot.max_speed = P.robot_max_speed;
  s.robot.max_accel = P.robot_max_accel;
  s.robot.start = Vec2(P.start_x, rng.uniform(-P.endpoint_y_range, P.endpoint_y_range));
  const Vec2 goal(P.goal_x, rng.uniform(-P.endpoint_y_range, P.endpoint_y_range));
  s.robot.goals = {goal};
  s.robot.start_yaw = 0.0;  // facing +x, towards the goal side (the base is omnidirectional)

  const double lim = P.half_size;
  // Static obstacles: rejection sampling with a bounded number of tries per obstacle.
  for (int i = 0; i < P.num_static; ++i) {
    for (int attempt = 0; attempt < 2000; ++attempt) {
      StaticObstacle o;
      if (i % 2 == 0) {
        o.kind = ShapeKind::kCylinder;
        o.radius = rng.uniform(P.static_cylinder_r_min, P.static_cylinder_r_max);
      } else {
        o.kind = ShapeKind::kBox;
        o.half_size = 0.5 * Vec2(rng.uniform(P.static_box_side_min, P.static_box_side_max),
                                 rng.uniform(P.static_box_side_min, P.static_box_side_max));
        o.yaw = rng.uniform(-0.25 * kTwoPi, 0.25 * kTwoPi);  // [-pi/2, pi/2): a box is symmetric
      }
      o.height = rng.uniform(P.static_height_min, P.static_height_max);
      o.reflectivity = rng.uniform(60.0, 160.0);
      const double br = boundRadius(o);
      o.center = Vec2(rng.uniform(-lim + br, lim - br), rng.uniform(-lim + br, lim - br));
      bool ok = (o.center - s.robot.start).norm() - br >= P.static_clear_radius &&
                (o.center - goal).norm() - br >= P.static_clear_radius;
      for (const auto& q : s.statics) {
        if (!ok) break;
        ok = (o.center - q.center).norm() - br - boundRadius(q) >= P.static_spacing;
      }
      if (ok) {
        s.statics.push_back(o);
        break;
      }
    }
  }

  // Moving obstacles.
  for (int i = 0; i < num_moving; ++i) {
    MovingObstacle m;
    m.id = i + 1;
    for (int attempt = 0; attempt < 5000; ++attempt) {
      m.radius = rng.uniform(P.mover_r_min, P.mover_r_max);
      m.height = rng.uniform(P.mover_height_min, P.mover_height_max);
      m.reflectivity = rng.uniform(30.0, 90.0);
      const Vec2 p(rng.uniform(-lim + m.radius, lim - m.radius),
                   rng.uniform(-lim + m.radius, lim - m.radius));
      bool ok = (p - s.robot.start).norm() >= P.mover_clear_radius + m.radius &&
                (p - goal).norm() >= P.mover_clear_radius + m.radius;
      for (const auto& q : s.statics) {
        if (!ok) break;
        ok = (p - q.center).norm() - boundRadius(q) - m.radius >= P.mover_spacing;
      }
      for (const auto& q : s.movers) {
        if (!ok) break;
        ok = (p - q.motion.position).norm() - q.radius - m.radius >= P.mover_spacing;
      }
      if (ok) {
        m.motion.position = p;
        break;
      }
      if (attempt == 4999) m.motion.position = p;  // crowded world: accept the last draw
    }
    MotionParams& mp = m.motion;
    switch (i % 3) {
      case 0:
        mp.kind = MotionKind::kConstantVelocity;
        mp.velocity = randomDirection(rng) * rng.uniform(P.speed_min, P.speed_max);
        break;
      case 1:
        mp.kind = MotionKind::kConstantAcceleration;
        mp.velocity = randomDirection(rng) * rng.uniform(P.speed_min, P.speed_max);
        mp.acceleration = randomDirection(rng) * rng.uniform(P.ca_accel_min, P.ca_accel_max);
        mp.speed_cap = P.speed_max;
        break;
      default: {
        mp.kind = MotionKind::kSinusoidal;
        mp.offset = randomDirection(rng) * rng.uniform(P.speed_min, P.sin_mean_speed_max);
        mp.amplitude = Vec2(rng.uniform(P.sin_amp_min, P.sin_amp_max),
                            rng.uniform(P.sin_amp_min, P.sin_amp_max));
        mp.omega = Vec2(rng.uniform(P.sin_omega_min, P.sin_omega_max),
                        rng.uniform(P.sin_omega_min, P.sin_omega_max));
        mp.phase = Vec2(rng.uniform(0.0, kTwoPi), rng.uniform(0.0, kTwoPi));
        // Peak speed bound: sqrt((|ox|+Ax)^2 + (|oy|+Ay)^2) <= speed_max.
        const double px = std::fabs(mp.offset.x()) + mp.amplitude.x();
        const double py = std::fabs(mp.offset.y()) + mp.amplitude.y();
        const double peak = std::sqrt(px * px + py * py);
        if (peak > P.speed_max) {
          const double k = P.speed_max / peak;
          mp.offset *= k;
          mp.amplitude *= k;
        }
        break;
      }
    }
    s.movers.push_back(m);
  }
  return s;
}

}  // namespace world
}  // namespace ucon
