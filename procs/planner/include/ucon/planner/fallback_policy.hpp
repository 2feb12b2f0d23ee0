#pragma once
/// @file fallback_policy.hpp
/// What the planner does in a cycle in which no plan toward the goal passed the trajectory
/// check: one policy, keep / evade / brake, with one score.
///
///  - keep: the plan being followed still passes the check: it goes out again.
///  - evade, checked: short detours, optimised toward the headings whose straight run scores
///    best, each still put through the check; the first that passes is followed.
///  - otherwise, by the score: the plan being followed (keep, it wins near ties), the least-bad
///    rejected plan or the best of a fan of manoeuvres (evade: a change of velocity at the
///    acceleration limit to one of `directions` headings at full or half the speed limit, held
///    for `run_s`, then braking at the limit), or braking (brake), whichever scores best.
///
/// Braking leaves the robot where it is, in the way of whatever is coming; the benchmark's
/// movers do not avoid the robot. The score of a trajectory is its smallest predicted gap to the
/// movers' bodies over the horizon (bodies grown by the predicted position's uncertainty), plus
/// a little for the mean gap and for progress toward the goal; trajectories that come closer to
/// static obstacles than the robot radius (or, starting closer, than they start) are out. The
/// same score ranks the detour headings, picks the least-bad rejected plan and makes the last
/// choice. Deterministic: fixed candidate order, ties keep the earlier candidate.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/trajopt/distance_field.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon {
class ConfigReader;
}

namespace ucon::planner {

/// YAML section `fallback` of planner.yaml.
struct FallbackParams {
  int detours = 3;              ///< optimised detours tried before the unchecked choice (0 = none), 0..16
  double detour_length = 2.5;   ///< length of a detour [m], 0.5..10
  int directions = 16;          ///< headings of the detours and of the manoeuvres, 4..64
  double run_s = 1.0;           ///< a manoeuvre holds its velocity this long after the start, then brakes [s]
  double horizon_s = 2.0;       ///< trajectories are scored over this [s] (at rest after their end)
  double step_s = 0.05;         ///< ... at this step [s]
  /// Gaps before this are nearly the same whatever the robot does now: not scored [s].
  double reaction_s = 0.1;
  double gap_cap = 1.0;         ///< gaps beyond this count as this much (far is far) [m]
  double uncertainty_k = 1.0;   ///< a body grows by this many standard deviations of its predicted position
  double mean_weight = 0.1;     ///< score per metre of mean (capped) gap, the tie-breaker of the smallest
  double goal_weight = 0.02;    ///< score per metre of progress toward the goal over the horizon
  /// The trajectory being followed is kept unless another scores better by more than this
  /// (no switching between near ties) [m of score].
  double keep_margin = 0.0;
  void read(ConfigReader& r);
};

/// Score of one trajectory (higher is safer).
struct FallbackScore {
  bool static_ok = false;       ///< no closer to static obstacles than allowed
  double min_gap = 0.0;         ///< smallest capped gap robot surface to grown body over the scored window [m]
  double mean_gap = 0.0;        ///< mean of the capped gaps (each step's nearest body) [m]
  double progress = 0.0;        ///< reduction of the distance to the goal over the horizon [m]
  double total = 0.0;           ///< min_gap + mean_weight * mean_gap + goal_weight * progress; -inf if !static_ok
};

/// Scores the robot (radius `robot_radius`) following `pp` from `from_utime` (at rest after its
/// end) against `field` (may be null: no static obstacles) and the constant-velocity
/// predictions of `obstacles` (non-finite ones skipped; without covariance they do not grow).
FallbackScore scoreTrajectory(const trajectory::PiecewisePolynomial& pp, int64_t from_utime,
                              const Eigen::Vector2d& goal, const trajopt::DistanceField2D* field,
                              const std::vector<trajopt::PredictedObstacle>& obstacles, double robot_radius,
                              const FallbackParams& params);

/// A manoeuvre from (p0, v0) at `t0`: constant acceleration `amax` toward velocity `u`, `u` held
/// until `run_s` after t0 (if the change takes longer, it is completed first), braking at `amax`
/// to rest, held for 0.5 s. 2-D, order1 = 6. False on non-finite input or amax <= 0.
bool manoeuvrePolynomial(int64_t t0, const Eigen::Vector2d& p0, const Eigen::Vector2d& v0,
                         const Eigen::Vector2d& u, double amax, double run_s,
                         trajectory::PiecewisePolynomial* out);

/// Heading k of `directions`: (cos, sin) of k 2 pi / directions.
Eigen::Vector2d heading(int k, int directions);

/// The detour headings, best first: each heading k's straight run from (p0, v0) at `t0`
/// (manoeuvrePolynomial toward `speed` along it, held for detour_length / speed) by
/// scoreTrajectory; ties in heading order. Headings whose run is out (static) are left out.
std::vector<int> rankHeadings(int64_t t0, const Eigen::Vector2d& p0, const Eigen::Vector2d& v0,
                              const Eigen::Vector2d& goal, double speed, double amax,
                              const trajopt::DistanceField2D* field,
                              const std::vector<trajopt::PredictedObstacle>& obstacles, double robot_radius,
                              const FallbackParams& params);

/// The best manoeuvre of the fan (directions x {vmax, vmax / 2}, each held for params.run_s),
/// by scoreTrajectory.
struct Manoeuvre {
  trajectory::PiecewisePolynomial pp;
  FallbackScore score;
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< the held velocity u [m/s]
};
/// Empty result (pp invalid) if no candidate is static_ok or the input is not finite.
Manoeuvre bestManoeuvre(int64_t t0, const Eigen::Vector2d& p0, const Eigen::Vector2d& v0, const Eigen::Vector2d& goal,
                        double vmax, double amax, const trajopt::DistanceField2D* field,
                        const std::vector<trajopt::PredictedObstacle>& obstacles, double robot_radius,
                        const FallbackParams& params);

/// The policy's unchecked choice.
enum class FallbackChoice {
  kBrake = 0,   ///< brake: nothing scores better than braking
  kKeep,        ///< keep the plan being followed (failed the check too, but scores best)
  kLeastBad,    ///< evade along the least-bad rejected plan
  kManoeuvre,   ///< evade by the best manoeuvre
};
const char* toString(FallbackChoice c);
/// Scores (FallbackScore::total; -inf for a candidate that does not exist) -> the choice: the
/// plan being followed if it beats braking and comes within keep_margin of the best; else the
/// manoeuvre if it beats braking and the least-bad plan; else the least-bad plan if it beats
/// braking; else braking.
FallbackChoice chooseFallback(double braking, double kept, double least_bad, double manoeuvre,
                              double keep_margin);

}  // namespace ucon::planner
