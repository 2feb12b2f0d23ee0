#pragma once
/// @file observation.hpp
/// How the planning benchmark observes the moving obstacles (issue 31): the stand-in for
/// perception that turns the world's true mover states into the tracks the planner is given.
///
/// - all: every mover is measured every frame (true centre plus Gaussian noise) and has one
///   track for the whole run, as if the LiDAR saw everything (the closed loop's original
///   condition: after a second every track has the same converged covariance).
/// - los: a mover is measured only while the sensor has line of sight to it within a range, as
///   a LiDAR on the robot has it: static obstacles and other movers occlude. A new track starts
///   with zero velocity and the filter's initial velocity sigma; a hidden track coasts (its
///   covariance grows through the filter's prediction, its velocity decays as perception's
///   does) and is dropped after the coast time; a mover seen again after that gets a new track.
///   So covariances differ from track to track.
/// Tracks are the project's constant-velocity Kalman filter (common/kalman), updated with the
/// noisy centre (position only) and association is perfect (the benchmark measures planning).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/perception/outputs.hpp"
#include "ucon/world/rng.hpp"
#include "ucon/world/world.hpp"

namespace ucon::bench {

enum class ObserveMode { kAll, kLineOfSight };
const char* toString(ObserveMode m);  ///< "all" | "los"
bool parseObserveMode(const std::string& s, ObserveMode* out);

struct ObserveConfig {
  ObserveMode mode = ObserveMode::kAll;
  double range = 12.0;          ///< los: movers farther than this (centre) are not seen [m]
  double sensor_height = 0.5;   ///< los: sensor above the robot's centre (perception sensor_origin z) [m]
  double noise_std = 0.05;      ///< centre noise (1 sigma, per axis) [m]
  kalman::KalmanParams kalman;  ///< the tracks' filter (position_std should be noise_std)
  /// los: a track unseen this long is dropped (the Table II protocol's own value) [s]
  double max_coast = 3.0;
  /// los: the velocity of an unseen track decays with this time constant (perception.yaml
  /// tracks.coast_velocity_decay) [s]; 0 = off
  double coast_velocity_decay = 1.0;
};

/// True if the sensor at (`sensor`, height `sensor_height`) sees mover `i` of `w` at w.time():
/// its centre within `range`, and a horizontal ray to its centre or to either side of its
/// body (0.8 of its radius across the line of sight) first meets that mover, not a static
/// obstacle or another mover.
bool lineOfSight(const world::World& w, const Eigen::Vector2d& sensor, double sensor_height, std::size_t i,
                 double range);

/// One mover's current track.
struct Track {
  bool live = false;            ///< a track exists (seen within max_coast)
  int64_t id = 0;               ///< track id (all: the mover's id; los: a new id per track)
  double created_s = 0.0;       ///< world time the track started [s]
  double last_seen_s = 0.0;     ///< world time of its last measurement [s]
  int frames = 0;               ///< frames since it started
  kalman::ConstantVelocityKalman kf;
};

class Observer {
 public:
  Observer(const world::World& w, const ObserveConfig& cfg, uint64_t seed);

  /// One frame at `w.time()` (call after World::setTime), `dt` after the previous frame [s],
  /// the sensor at `sensor`: measures what can be seen, updates or coasts the tracks and
  /// returns the live ones as perception publishes them.
  std::vector<perception::ObjectEstimate> frame(double dt, const Eigen::Vector2d& sensor);

  /// Per mover (index into w.movers()).
  const std::vector<Track>& tracks() const { return tracks_; }
  /// The mover whose live track has `id`; -1 for none.
  int moverOfTrack(int64_t id) const;
  /// Seconds the track of mover `i` has existed at w.time(); nullopt when it has none.
  std::optional<double> trackAge(std::size_t i) const;
  /// Measurements taken and frames in which a live track went unseen (los statistics).
  int64_t measurements() const { return measurements_; }
  int64_t coastingFrames() const { return coasting_; }
  int64_t tracksStarted() const { return started_; }

 private:
  const world::World& w_;
  ObserveConfig cfg_;
  world::Rng noise_;
  std::vector<Track> tracks_;
  int64_t next_id_ = 1;
  int64_t measurements_ = 0, coasting_ = 0, started_ = 0;
};

}  // namespace ucon::bench
