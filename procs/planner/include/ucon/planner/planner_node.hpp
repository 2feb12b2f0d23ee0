#pragma once
/// @file planner_node.hpp
/// The planner node: map, goal, obstacles and pose in; a receding-horizon sector-MINCO
/// trajectory out at `rate_hz`. No LCM, no wall clock in decisions (plan timings are measured
/// with a steady clock and only reported).

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ucon/cell_age.hpp"
#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/message_clock.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/planner/esdf_map.hpp"
#include "ucon/planner/fallback_policy.hpp"
#include "ucon/planner/guide_path.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/status_report.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/trajopt/sector_minco.hpp"

namespace ucon::planner {

/// What one planning cycle ended with (the PLANNER_STATUS value "result").
enum class PlanResult {
  kOk = 0,            ///< a checked trajectory was published
  kGoalReached,       ///< within tolerance: hold position, goal dropped
  kStopNoFeasible,    ///< the optimiser found nothing safe: stopping trajectory
  kStopNoPose,        ///< no valid, fresh pose
  kStopNoMap,         ///< no static map yet
  kStopStaleObjects,  ///< obstacles too old to trust
  kCancelled,         ///< goal cancelled: stopping trajectory
  kKeptPrevious,      ///< the new result failed its check; the previous plan is still safe
};
const char* toString(PlanResult r);

/// Per-plan report (also written into the StatusReport).
struct PlanInfo {
  PlanResult result = PlanResult::kOk;
  std::string message;
  double map_ms = 0.0, front_end_ms = 0.0, optimize_ms = 0.0, check_ms = 0.0, total_ms = 0.0;
  int iterations = 0;
  double cost_total = 0.0, cost_energy = 0.0, cost_time = 0.0, cost_static = 0.0,
         cost_dynamic = 0.0, cost_feasibility = 0.0;
  GuideStatus guide = GuideStatus::kOk;
  bool triggered_by_unsafe = false;  ///< replanned early because the current plan became unsafe
};

/// What a handler asks the process to publish.
struct PlannerOutputs {
  std::optional<trajectory_t> trajectory;  ///< PLANNER_TRAJECTORY
  std::optional<PlanInfo> plan;            ///< set when a planning cycle ran
};

class PlannerNode {
 public:
  /// `report` collects counters, timings and gauges for PLANNER_STATUS; it must outlive the node.
  PlannerNode(const PlannerParams& params, StatusReport& report);
  ~PlannerNode();
  PlannerNode(const PlannerNode&) = delete;
  PlannerNode& operator=(const PlannerNode&) = delete;

  void onPose(const robot_pose_t& msg);
  void onObjects(const tracked_objects_t& msg);
  void onStatic(const static_points_t& msg);
  /// A new goal replans on the next tick; a cancel publishes a stopping trajectory there.
  void onGoal(const nav_goal_t& msg);
  /// Advances "now" to `utime` [us] and replans when due (rate, new goal, unsafe current plan).
  PlannerOutputs tick(int64_t utime);

  /// The map (benchmarks build it from known geometry; tests inspect it). Call
  /// notifyMapChanged() after writing to it directly.
  EsdfMap& map() { return map_; }
  const EsdfMap& map() const { return map_; }
  /// Ray-inserts the static frames gathered so far (tick() does this every
  /// static_insert_period_s; tests and benchmarks may force it).
  void flushStaticPoints();
  void notifyMapChanged() {
    map_dirty_ = true;
    map_received_ = true;
  }
  /// Brings the ESDF up to date around `xy` now (set-up before the first plan, so the first
  /// plan does not pay for building the distance transform).
  void prepareMap(const Eigen::Vector2d& xy) {
    map_.update(xy, true);
    map_dirty_ = false;
    map_received_ = true;
  }
  const MessageClock& clock() const { return clock_; }
  /// The trajectory last published (empty before the first).
  const trajectory::PiecewisePolynomial& currentTrajectory() const { return current_; }
  bool hasGoal() const { return goal_.has_value(); }
  const PlannerParams& params() const { return params_; }
  /// Obstacles accepted from the last objects message (a bad covariance is replaced by the
  /// conservative fallback of ObjectParams).
  const std::vector<trajopt::PredictedObstacle>& obstacles() const { return obstacles_; }

  /// The optimiser's post-check (static clearance, predicted obstacle bodies within the check
  /// horizon, limits) of `traj` from `from_utime` on against the current map and obstacles.
  trajopt::SafetyCheck check(const trajectory_t& traj, int64_t from_utime) const;

  /// The problem a plan at `utime` would give the optimiser first: the start at utime +
  /// latency (startState), the nominal initial guess along the guide path (searchGuidePath),
  /// the map and the obstacles. Empty where such a plan stops before optimising (inputs
  /// missing or stale, goal reached, no usable guide path, no progress possible). Observes
  /// the clock and brings the map up to date as tick() does, publishes nothing and leaves the
  /// plan being followed alone; a tick() at the same `utime` afterwards plans as it would
  /// have. The benchmark's open-loop protocol solves it with every obstacle model.
  std::optional<trajopt::PlanRequest> problem(int64_t utime);

 private:
  /// Start of a plan: position, velocity, acceleration at `utime`.
  struct StartState {
    int64_t utime = 0;
    Eigen::Vector2d p = Eigen::Vector2d::Zero();
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    Eigen::Vector2d a = Eigen::Vector2d::Zero();
  };
  /// One planning cycle under way: when it began and what it reports.
  struct Cycle {
    int64_t now = 0;
    bool unsafe_trigger = false;  ///< the plan being followed became unsafe
    std::chrono::steady_clock::time_point t_start;  ///< compute-time measurement only
    PlanInfo info;
  };

  /// The map as the optimiser's distance field; null until the ESDF was first updated.
  const trajopt::DistanceField2D* staticField() const;
  PlannerOutputs plan(int64_t now, bool unsafe_trigger);
  // The steps of plan(), in order (planner_node.cpp).
  /// Why the inputs cannot be planned with (no fresh pose, no map, stale obstacles), if so.
  std::optional<PlanResult> missingInput() const;
  bool goalReached() const;
  /// The current plan at now + latency when the robot follows it, else the pose.
  StartState startState(int64_t now);
  /// Brings the ESDF up to date when the map changed or the robot left the box's centre.
  void updateMap(const Eigen::Vector2d& start, PlanInfo* info);
  /// The front end: A* guide path from the start toward the goal.
  GuidePath searchGuidePath(const Eigen::Vector2d& start, PlanInfo* info) const;
  /// Why the guide path does not end at the goal (empty when it does); counted on the status.
  std::string noteOnGuide(const GuidePath& guide);
  /// Initial guess of optimiser run `attempt` along the guide: 0 nominal, then slower, then
  /// shorter as well.
  InitialGuess initialGuess(const GuidePath& guide, const StartState& start, int attempt) const;
  /// The optimiser's request from `start` (guess and goal left to fill).
  trajopt::PlanRequest requestFrom(const StartState& start) const;
  /// The optimiser's runs toward the goal (max_attempts), until one passes its check.
  trajopt::PlanOutput optimise(const StartState& start, const GuidePath& guide, Cycle& cycle);
  /// The front end gave nothing to optimise along (no map, start outside it, bad input).
  static bool guideUnusable(const GuidePath& guide);
  /// The plan being followed still passes the check (and did not trigger this cycle).
  bool previousStillSafe(const Cycle& cycle) const;
  void reportOptimiserResult(const trajopt::PlanOutput& po, PlanInfo* info);
  /// The optimiser's result passed its post-check (static clearance, predicted obstacles,
  /// limits): `pp` is the trajectory to follow. Reports the result either way.
  bool passedCheck(const trajopt::PlanOutput& po, trajectory::PiecewisePolynomial* pp, PlanInfo* info);
  // How a cycle ends.
  PlannerOutputs stop(Cycle& cycle, PlanResult result, const std::string& message);
  PlannerOutputs follow(Cycle& cycle, const trajectory::PiecewisePolynomial& pp, const std::string& message);
  /// The current plan goes out again, stamped now: the base controller stops on a trajectory
  /// older than its watchdog (0.2 s), and a planner that keeps its plan for two cycles in a
  /// row must not look like a silent one.
  PlannerOutputs keep(Cycle& cycle, const std::string& info_message, const std::string& message);
  PlannerOutputs reachGoal(Cycle& cycle);
  /// Nothing toward the goal passed the check (`rejected`: the last run): the fallback policy
  /// (fallback_policy.hpp) keeps the plan being followed, evades or brakes.
  PlannerOutputs fallBack(Cycle& cycle, const StartState& start, const trajopt::PlanOutput& rejected);
  /// Standing still from `now` (the stop trajectory) is predicted to be hit: the robot's disk
  /// reaches a mover's body grown by fallback.uncertainty_k std within fallback.horizon_s.
  bool holdIsHit(int64_t now) const;
  PlannerOutputs conclude(Cycle& cycle, trajectory_t trajectory);

  // The fallback policy's parts (planner_fallback.cpp).
  /// FallbackScore of the robot following `pp` from `from_utime` among the current obstacles.
  FallbackScore score(const trajectory::PiecewisePolynomial& pp, int64_t from_utime) const;
  /// Optimised detours toward the best-scoring headings (fallback.detours); true, with the
  /// detour in `detour`, when one passes the check. Failed ones join the least-bad candidates.
  bool tryDetours(const StartState& start, Cycle& cycle, trajectory::PiecewisePolynomial* detour);
  /// Keeps `po` as a candidate for this cycle's least-bad plan if it failed only on predicted
  /// obstacles (static clearance and limits fine).
  void keepIfLeastBadCandidate(const trajopt::PlanOutput& po);
  /// Position and velocity the robot is expected to have at now + latency: the current plan's
  /// (the pose's if the robot is off it), else the pose's; false without a finite state.
  bool expectedState(int64_t now, Eigen::Vector2d* p, Eigen::Vector2d* v) const;
  /// The braking polynomial stopTrajectory() publishes; false without a state to stop from.
  bool stopPolynomial(int64_t now, trajectory::PiecewisePolynomial* pp) const;

  // Outputs (planner_outputs.cpp).
  trajectory_t stopTrajectory(int64_t now, int8_t status, const std::string& message);
  trajectory_t finish(const trajectory::PiecewisePolynomial& pp, int64_t now, int8_t status,
                      const std::string& message);
  /// The current plan again (same plan_id and curve), stamped `now` with a new seq and this message.
  trajectory_t resend(int64_t now, const std::string& message);
  void record(const PlanInfo& info);

  PlannerParams params_;
  StatusReport& report_;
  EsdfMap map_;
  /// Since when each map column has had static points (PlannerParams: objects.clear_max_age).
  CellAge static_age_;
  MessageClock clock_;
  std::optional<robot_pose_t> pose_;
  std::vector<trajopt::PredictedObstacle> obstacles_;
  /// This cycle's rejected plans that failed only on predicted obstacles (least-bad candidates).
  std::vector<trajectory::PiecewisePolynomial> rejected_;
  int64_t objects_utime_ = 0;
  bool objects_seen_ = false;
  std::optional<nav_goal_t> goal_;
  bool goal_changed_ = false;
  bool cancel_pending_ = false;
  bool map_dirty_ = false;
  bool map_received_ = false;
  std::string pending_message_;
  int64_t static_frames_ = 0;
  // Static frames gathered since the last ray insertion (see PlannerParams::static_insert_period_s).
  std::vector<Eigen::Vector3f> pending_points_;
  Eigen::Vector3d pending_origin_ = Eigen::Vector3d::Zero();
  double pending_range_ = 0.0;
  int64_t last_insert_utime_ = 0;
  trajectory::PiecewisePolynomial current_;
  trajectory_t current_msg_{};
  int8_t current_status_ = trajectory_t::STATUS_INVALID;
  int64_t last_plan_utime_ = 0;
  int64_t seq_ = 0;
  int64_t plan_id_ = 0;
  class Field;  // EsdfMap as trajopt::DistanceField2D
  std::unique_ptr<Field> field_;
  trajopt::TrajectoryOptimizer optimizer_;
};

}  // namespace ucon::planner
