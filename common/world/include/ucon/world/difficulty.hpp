#pragma once
/// @file difficulty.hpp
/// How hard a scenario is for perception, counted from ground truth (issue 3: the
/// `pedestrians` scenario must give, for every seed, at least 10 of each per 243 s).
///
/// Sampled every `dt` seconds over [0, duration]:
///  - close pass: two movers' centres come closer than `close_pass_m`; an episode ends when
///    they are farther than `close_release_m` again (hysteresis, so one pass counts once).
///  - static pass: a mover's body surface comes within `static_pass_m` of a static obstacle's
///    footprint (surface-to-surface gap, the gap a clustering step has to split); ends above
///    `static_release_m`.
///  - occlusion: the line of sight from the sensor to a mover's centre (2-D) crosses another
///    mover's disk or the footprint of a static obstacle at least as tall as the sensor, for at
///    least `min_occlusion_s` without interruption; movers beyond `max_range_m` are ignored.

#include <string>

#include "ucon/world/world.hpp"

namespace ucon {
namespace world {

struct DifficultyParams {
  double close_pass_m = 0.8;       ///< [m]
  double close_release_m = 1.0;    ///< [m]
  double static_pass_m = 0.4;      ///< [m]
  double static_release_m = 0.6;   ///< [m]
  double min_occlusion_s = 0.3;    ///< [s]
  double max_range_m = 40.0;       ///< [m]
  double dt = 0.02;                ///< sampling step [s] (the 50 Hz LiDAR frame period)
};

struct DifficultyCounts {
  int close_passes = 0;
  int static_passes = 0;
  int occlusions = 0;               ///< total (each episode once)
  int occlusions_by_mover = 0;      ///< episodes whose first occluder was a mover
  int occlusions_by_static = 0;     ///< episodes whose first occluder was a static obstacle
  double min_mover_distance = 0.0;  ///< smallest centre distance between two movers [m]
  double duration_s = 0.0;          ///< time examined [s]

  /// "close passes 14, static passes 22, occlusions 17 (9 by movers, 8 by static) in 243 s".
  std::string toString() const;
};

/// Counts over [0, duration_s] with the sensor at `sensor` (x, y, z [m], fixed).
DifficultyCounts computeDifficulty(const World& world, const Vec3& sensor, double duration_s,
                                   const DifficultyParams& params = DifficultyParams{});

/// Share (0..1) of mover `i`'s silhouette that a sensor at `sensor` sees at the world's current
/// time (World::setTime): rays towards a grid of `columns` x `rows` points spread across the
/// mover's width and height (its visible side) that hit that mover first, within `max_range`
/// [m]. For ground-truth evaluation: a tracker cannot be blamed for an object it cannot see.
double moverVisibility(const World& world, std::size_t i, const Vec3& sensor, int columns = 7,
                       int rows = 5, double max_range = 40.0);

}  // namespace world
}  // namespace ucon
