#pragma once
/// @file world.hpp
/// Evaluates a Scenario: moving-obstacle states as a pure function of time, and geometric
/// queries (ray casting, disk contact/clearance, distance to the nearest surface) against the
/// world at one instant.
///
/// Bounce: constant-velocity, constant-acceleration and sinusoidal motions are evaluated in an
/// unbounded plane and folded into [min + r, max - r] per axis (mirror reflection). After a bounce
/// the obstacle moves in the mirrored world, so the velocity *and* the acceleration component
/// normal to the border flip; this keeps the state a closed-form function of t.
/// Pedestrians follow a piecewise-linear timeline drawn once from (scenario seed, obstacle id).
///
/// Queries use a uniform 2-D grid over the bounds (static obstacles binned once, moving ones
/// re-binned by setTime()). Moving obstacles do not interact with each other or with static
/// obstacles (as in the paper's benchmark world, they pass through each other).

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "ucon/world/scenario.hpp"

namespace ucon {
namespace world {

/// State of one moving obstacle at one time.
struct ObstacleState {
  int64_t id = 0;
  Vec2 position = Vec2::Zero();  ///< centre [m]
  Vec2 velocity = Vec2::Zero();  ///< [m/s]
  double radius = 0.0;           ///< [m]
  double height = 0.0;           ///< [m]
  MotionKind motion = MotionKind::kConstantVelocity;
};

/// What a ray or a contact query found.
enum class HitKind : uint8_t { kNone = 0, kGround = 1, kStatic = 2, kMoving = 3 };

/// Result of castRay().
struct RayHit {
  HitKind kind = HitKind::kNone;
  double range = std::numeric_limits<double>::infinity();  ///< distance along the ray [m]
  int index = -1;                ///< index into statics or movers, -1 for ground/none
  Vec3 normal = Vec3::UnitZ();   ///< unit surface normal at the hit (towards the ray origin side)
  double reflectivity = 0.0;     ///< the surface's reflectivity at normal incidence, 0..255
};

/// Result of diskContact().
struct Contact {
  double clearance = std::numeric_limits<double>::infinity();  ///< min surface gap [m]; < 0 = overlap
  HitKind kind = HitKind::kNone;  ///< nearest obstacle's kind (kStatic / kMoving / kNone)
  int index = -1;                 ///< its index
  bool collision() const { return clearance < 0.0; }
};

/// One straight-line piece of a pedestrian's timeline.
struct TimelineSegment {
  double t0 = 0.0;               ///< start time [s]
  Vec2 p0 = Vec2::Zero();        ///< position at t0 [m]
  Vec2 v = Vec2::Zero();         ///< velocity on the piece [m/s] (0 = pause)
};

/// Mirror-folds an unbounded coordinate `u` moving at `v` into [lo, hi]; returns the folded
/// position and sets `sign` to +1 or -1 (the factor applied to velocity and acceleration).
double foldIntoInterval(double u, double lo, double hi, double* sign);

class World {
 public:
  struct Options {
    double cell_size = 1.0;             ///< grid cell [m], > 0
    double timeline_horizon_s = 0.0;    ///< pedestrian timelines cover [0, this]; 0 = max(duration, 3600)
    double ground_reflectivity = 20.0;  ///< reflectivity of the ground plane, 0..255
  };

  /// The scenario must be valid (validate() returned nullopt).
  explicit World(Scenario scenario);
  World(Scenario scenario, const Options& options);

  const Scenario& scenario() const { return scenario_; }
  const Options& options() const { return options_; }
  std::size_t numMovers() const { return scenario_.movers.size(); }

  /// State of mover `i` at time `t` [s] (t < 0 is clamped to 0). Pure: no dependence on setTime().
  ObstacleState moverState(std::size_t i, double t) const;
  /// States of all movers at time t into `out` (resized).
  void moverStates(double t, std::vector<ObstacleState>& out) const;
  /// The timeline of pedestrian mover `i` (empty for other motions).
  const std::vector<TimelineSegment>& timeline(std::size_t i) const { return timelines_[i]; }

  /// Moves the dynamic layer to time `t` [s]: mover states and their grid cells.
  void setTime(double t);
  double time() const { return time_; }
  /// Mover states at time().
  const std::vector<ObstacleState>& movers() const { return states_; }

  /// First surface (obstacle side or top, or the ground z = 0) hit by the ray from `origin`
  /// along unit vector `dir` within `max_range` [m], at time(). Non-finite input: kNone.
  RayHit castRay(const Vec3& origin, const Vec3& dir, double max_range) const;

  /// Smallest gap between a disk (centre, radius [m]) and any obstacle at time(). A non-finite
  /// input gives a NaN clearance (collision() false) and kind kNone.
  Contact diskContact(const Vec2& center, double radius) const;

  /// diskContact() against the static obstacles only (they do not depend on time()): kind
  /// kStatic with the nearest one's index, or infinity and kNone without static obstacles.
  Contact staticContact(const Vec2& center, double radius) const;

  /// Distance from point `p` to the nearest surface (obstacle or ground) at time(), capped at
  /// `cap` [m] (obstacles farther than `cap` in the plane are not examined). NaN for a
  /// non-finite point.
  double surfaceDistance(const Vec3& p, double cap) const;

  /// Signed 2-D distance from `p` to the footprint of static obstacle `i` (< 0 inside) [m].
  double staticFootprintDistance(std::size_t i, const Vec2& p) const;

  /// True if the 2-D segment a->b crosses (or touches) the footprint of static `i`.
  bool segmentHitsStatic(std::size_t i, const Vec2& a, const Vec2& b) const;

  /// Tallest obstacle [m].
  double maxHeight() const { return max_height_; }

 private:
  void buildTimelines();
  void buildStaticGrid();
  int cellIndex(int cx, int cy) const { return cy * nx_ + cx; }
  void cellRange(double x0, double y0, double x1, double y1, int* cx0, int* cy0, int* cx1,
                 int* cy1) const;
  bool rayStatic(std::size_t i, const Vec3& o, const Vec3& d, double* t, Vec3* n) const;
  bool rayMover(std::size_t i, const Vec3& o, const Vec3& d, double* t, Vec3* n) const;
  /// moverState with a per-mover hint of the pedestrian timeline piece (updated; null: none).
  ObstacleState moverState(std::size_t i, double t, std::size_t* segment_hint) const;
  static std::size_t segmentAfter(const std::vector<TimelineSegment>& tl, double t, std::size_t* hint);

  Scenario scenario_;
  Options options_;
  std::vector<std::vector<TimelineSegment>> timelines_;
  // Precomputed per static: cos/sin of yaw.
  std::vector<double> cos_yaw_, sin_yaw_;
  double max_height_ = 0.0;

  // Grid.
  double gx0_ = 0, gy0_ = 0, cell_ = 1.0, inv_cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<int> static_start_, static_items_;
  std::vector<int> mover_start_, mover_items_, mover_fill_;
  std::vector<std::array<int, 4>> mover_ranges_;  // cells (x0, y0, x1, y1) of each mover in the grid
  std::vector<std::size_t> segment_hints_;        // per mover: setTime's last timeline answer

  double time_ = 0.0;
  std::vector<ObstacleState> states_;
};

}  // namespace world
}  // namespace ucon
