#pragma once
/// @file guide_path.hpp
/// The planner's front end: A* on the inflated 2-D occupancy of the ESDF slice, from the robot
/// to the goal or to the edge of the local window toward the goal, then line-of-sight
/// shortcutting and resampling into MINCO's initial waypoints and durations.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ucon/planner/esdf_map.hpp"

namespace ucon {
class ConfigReader;
}

namespace ucon::planner {

/// Front-end parameters (YAML section `front_end`).
struct FrontEndParams {
  double inflation = 0.6;        ///< guide path prefers this clearance from static obstacles [m], >= 0
  double hard_clearance = 0.3;   ///< cells closer than this are blocked [m], <= inflation
  double soft_cost = 4.0;        ///< extra cost factor at hard_clearance, fading to 0 at inflation, >= 0
  double window_radius = 6.0;    ///< the search stops at this distance from the robot [m], > 0
  int max_expansions = 60000;    ///< A* node budget, > 0
  double piece_length = 1.2;     ///< MINCO piece length along the guide path [m], > 0
  int max_pieces = 8;            ///< at most this many MINCO pieces, 1..64
  double guess_speed_ratio = 0.8;  ///< initial durations assume this share of the speed limit, 0.1..1
  double guess_accel_ratio = 0.5;  ///< ... and this share of the acceleration limit, 0.1..1

  void read(ConfigReader& r);
};

/// Outcome of the guide-path search.
enum class GuideStatus {
  kOk = 0,           ///< reaches the goal, or the window edge toward it
  kGoalInCollision,  ///< the goal lies inside the inflated obstacles: the path ends at the
                     ///< nearest reachable safe point instead
  kGoalUnreachable,  ///< no path within the window: the path ends at the nearest reachable point
  kStartOutsideMap,  ///< the robot is outside the ESDF slice
  kNoMap,            ///< the map has never been updated
  kBadInput,         ///< non-finite start or goal
};
const char* toString(GuideStatus s);

struct GuidePath {
  GuideStatus status = GuideStatus::kNoMap;
  std::vector<Eigen::Vector2d> points;  ///< start ... end, shortcut polyline [m]
  bool reaches_goal = false;            ///< the last point is the goal itself
  int expansions = 0;                   ///< A* nodes expanded
};

/// A* (8-connected, octile costs, Euclidean heuristic to the goal) over the slice cells whose
/// signed distance is >= hard_clearance; cells between hard_clearance and inflation cost more
/// (so narrow gaps are used only when needed, and a robot inside one is never trapped).
/// Cells closer than hard_clearance are entered only while the distance does not decrease, so
/// a robot that starts too close to an obstacle can leave. A goal closer than hard_clearance
/// to an obstacle is "in collision".
/// Ends at the goal's cell when the goal is within the window, otherwise at the first cell
/// popped at the window radius (its cost-to-go is the straight line to the goal).
GuidePath findGuidePath(const EsdfMap& map, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                        const FrontEndParams& params);

/// True if the straight segment a-b keeps signed distance >= clearance (sampled at res/4).
bool segmentClear(const EsdfMap& map, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                  double clearance);

/// Initial MINCO guess along a polyline: inner waypoints and piece durations.
struct InitialGuess {
  std::vector<Eigen::Vector2d> waypoints;  ///< inner waypoints, size = pieces - 1 [m]
  Eigen::Vector2d end = Eigen::Vector2d::Zero();  ///< tail position [m]
  std::vector<double> durations;           ///< per piece [s], > 0
  double length = 0.0;                     ///< path length used [m]
};

/// Resamples `path` (truncated to `max_length` metres) into pieces of about piece_length,
/// with durations from a trapezoidal speed profile: start speed `v0` [m/s], cruise `v_max`,
/// acceleration `a_max`, ending at rest. Empty pieces (path shorter than 1 cm) give one piece
/// with a small positive duration.
InitialGuess makeInitialGuess(const std::vector<Eigen::Vector2d>& path, double max_length,
                              double v0, double v_max, double a_max, const FrontEndParams& params);

}  // namespace ucon::planner
