#pragma once
/// @file open_loop.hpp
/// The open-loop, paired protocol of the planning benchmark (issue 31). A reference policy
/// drives the robot: the sector planner's own closed loop (closed_loop.hpp), shuttling between
/// start and goal. At every probe time the planner node's own problem (PlannerNode::problem:
/// start at now + latency, the guide path's initial guess, the map, the obstacles as tracked)
/// is solved by every method with its dynamic cost and check covering the evaluation horizon,
/// and each raw plan is played against the movers' true motion (probe.hpp). Every method is
/// given exactly the same problems, so the outcomes pair up plan by plan.

#include <cstdint>
#include <string>
#include <vector>

#include "closed_loop.hpp"
#include "probe.hpp"
#include "ucon/trajopt/sector_minco.hpp"
#include "ucon/world/scenario.hpp"

namespace ucon::bench {

struct OpenLoopConfig {
  RunConfig run;                     ///< the reference run (its method drives the robot)
  std::vector<std::string> methods;  ///< obstacle models solving each problem
  std::vector<double> horizons;      ///< evaluation horizons [s]; dynamic_horizon = check_horizon = each
};

/// One method's plan for one problem at one horizon.
struct PlanOutcome {
  bool has_plan = false;      ///< the optimiser produced a trajectory (checked or not)
  bool passed_check = false;  ///< ... and it passed the optimiser's post-check
  trajopt::PlanStatus status = trajopt::PlanStatus::kInvalidInput;  ///< the optimiser's verdict (why the check failed)
  PlayResult play;            ///< played against the true motion (no plan: not contact-free)
  bool hit_tracked = false;   ///< the mover touched first had a track in the problem
  double plan_ms = 0.0, plan_cpu_ms = 0.0;
  int iterations = 0;
  bool contactFree() const { return has_plan && play.contactFree(); }
  /// Avoidable: no contact, or the first mover touched was tracked (a static contact counts).
  bool avoidable() const { return !has_plan || !play.mover_contact || hit_tracked; }
};

struct ProbeRecord {
  double t = 0.0;                   ///< world time [s]
  int nearest = -1;                 ///< mover nearest to the robot (surface gap) at t
  world::MotionKind nearest_kind = world::MotionKind::kConstantVelocity;
  double nearest_gap = 0.0;         ///< [m]
  double nearest_track_age = -1.0;  ///< its track's age [s]; < 0: not tracked
  int obstacles = 0;                ///< obstacles in the problem
  std::vector<PlanOutcome> outcomes;  ///< [horizon index * methods + method index]
};

struct OpenLoopResult {
  RunResult run;                    ///< the reference run
  std::vector<ProbeRecord> probes;
  int skipped = 0;                  ///< probe times at which the node had no problem to solve
};

OpenLoopResult runOpenLoop(const planner::PlannerParams& params, const OpenLoopConfig& cfg);

}  // namespace ucon::bench
