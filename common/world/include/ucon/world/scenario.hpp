#pragma once
/// @file scenario.hpp
/// The description of a simulated world: static obstacles, moving obstacles with their motion
/// laws, the bounds they bounce off, and the robot's start and goals. Plain value types; the
/// World (world.hpp) evaluates them. Units: metres, seconds, radians; z up, obstacles stand on
/// the ground (z = 0) and extend to `height`.

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ucon {
namespace world {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

/// Footprint shape of a static obstacle (walls are boxes).
enum class ShapeKind : uint8_t { kCylinder = 0, kBox = 1 };

/// A static vertical prism standing on the ground.
struct StaticObstacle {
  ShapeKind kind = ShapeKind::kCylinder;
  Vec2 center = Vec2::Zero();     ///< footprint centre [m], world frame
  double radius = 0.5;            ///< cylinder radius [m] (kCylinder), > 0
  Vec2 half_size = Vec2(0.5, 0.5);  ///< box half extents along its own x/y axes [m] (kBox), > 0
  double yaw = 0.0;               ///< box orientation [rad] (kBox)
  double height = 2.0;            ///< top of the prism [m], > 0
  double reflectivity = 100.0;    ///< Livox reflectivity 0..255 at normal incidence
};

/// Motion law of a moving obstacle (values match sim_object_t::MOTION_*).
enum class MotionKind : uint8_t {
  kConstantVelocity = 0,
  kConstantAcceleration = 1,
  kSinusoidal = 2,
  kPedestrian = 3,
};

/// How a pedestrian chooses its next waypoint.
enum class PathMode : uint8_t {
  kLoop = 0,      ///< w0, w1, ..., wn-1, w0, ...
  kPingPong = 1,  ///< w0, ..., wn-1, wn-2, ..., w0, w1, ...
  kRandom = 2,    ///< any waypoint other than the current one, uniformly
};

/// Parameters of every motion law; only the fields of `kind` are used.
///
/// Constant velocity and acceleration and the sinusoid are defined in an unbounded plane and
/// folded into the bounds (mirror bounce, see world.hpp); pedestrians stay on their waypoints.
struct MotionParams {
  MotionKind kind = MotionKind::kConstantVelocity;
  Vec2 position = Vec2::Zero();  ///< position at t = 0 [m] (CV, CA, sinusoidal)
  Vec2 velocity = Vec2::Zero();  ///< velocity at t = 0 [m/s] (CV, CA)
  Vec2 acceleration = Vec2::Zero();  ///< [m/s^2] (CA)
  double speed_cap = 1.5;        ///< CA: speed stops growing at this value [m/s], > 0
  // Sinusoidal, per axis i (FAPP's simulator): v_i(t) = amplitude_i sin(omega_i t + phase_i) + offset_i.
  Vec2 amplitude = Vec2::Zero();  ///< [m/s]
  Vec2 omega = Vec2(1.0, 1.0);    ///< [rad/s], > 0
  Vec2 phase = Vec2::Zero();      ///< [rad]
  Vec2 offset = Vec2::Zero();     ///< [m/s]
  // Pedestrian.
  std::vector<Vec2> waypoints;    ///< >= 2 points [m]; starts at waypoints[0]
  PathMode mode = PathMode::kPingPong;
  double speed_min = 0.5;         ///< walking speed drawn uniformly in [min, max] [m/s]
  double speed_max = 1.8;
  double speed_change_min_s = 2.0;  ///< a new speed is drawn every U(min, max) seconds [s]
  double speed_change_max_s = 6.0;
  double pause_probability = 0.3;   ///< chance of stopping at a reached waypoint, 0..1
  double pause_min_s = 0.5;         ///< pause length U(min, max) [s]
  double pause_max_s = 3.0;
  double jitter = 0.0;  ///< each visit aims at the waypoint + U(-jitter, jitter) per axis [m]
};

/// A moving vertical cylinder.
struct MovingObstacle {
  int64_t id = 1;                ///< > 0, unique in the scenario
  double radius = 0.3;           ///< [m], > 0
  double height = 1.7;           ///< [m], > 0
  double reflectivity = 60.0;    ///< 0..255
  MotionParams motion;
};

/// Axis-aligned region the moving obstacles bounce inside (mirror reflection).
struct Bounds {
  double xmin = -25, xmax = 25, ymin = -25, ymax = 25;  ///< [m]
};

/// The robot of the scenario.
struct RobotSpec {
  Vec2 start = Vec2::Zero();  ///< [m]
  double start_yaw = 0.0;     ///< [rad]
  double radius = 0.3;        ///< disk radius used for collisions [m]
  double max_speed = 1.5;     ///< [m/s]
  double max_accel = 2.0;     ///< [m/s^2]
  std::vector<Vec2> goals;    ///< visited in order [m]
};

/// A complete world description.
struct Scenario {
  std::string name;           ///< e.g. "pedestrians", "bench:80:3"
  uint64_t seed = 1;          ///< seeds pedestrian timelines (and the generator that made it)
  double duration_s = 60.0;   ///< nominal length of a run [s], > 0
  Bounds bounds;
  RobotSpec robot;
  std::vector<StaticObstacle> statics;
  std::vector<MovingObstacle> movers;
};

/// Checks ranges and consistency; returns a message naming the bad field, or nullopt if valid.
std::optional<std::string> validate(const Scenario& s);

/// A wall from `a` to `b` of the given thickness and height, as a box.
StaticObstacle makeWall(const Vec2& a, const Vec2& b, double thickness, double height);

}  // namespace world
}  // namespace ucon
