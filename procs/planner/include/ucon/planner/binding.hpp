#pragma once
/// @file binding.hpp
/// ucon-planner's wiring, used by its main and by its replay adapter (see
/// ucon/runtime/binding.hpp): ROBOT_POSE, PERCEPTION_OBJECTS, PERCEPTION_STATIC and NAV_GOAL to
/// their handlers, then tick(now) after every input (live, also after 10 ms without one);
/// PLANNER_TRAJECTORY out; PLANNER_STATUS from the report the node writes into.

#include <string>

#include "ucon/channels.hpp"
#include "ucon/planner/planner_node.hpp"
#include "ucon/runtime/binding.hpp"

namespace ucon {
namespace planner {

/// The planner as its harnesses run it: the node, the status report it writes into, the last
/// plan message logged (a message is logged once, when it changes) and the planning cycles run.
struct BoundPlanner {
  explicit BoundPlanner(const PlannerParams& params) : node(params, status) {}
  StatusReport status{"planner"};  // declared before the node, which keeps a reference to it
  PlannerNode node;
  std::string last_message;
  int64_t plan_cycles = 0;
};

inline const runtime::Output<trajectory_t> kTrajectoryOutput{channels::kPlannerTrajectory};

inline runtime::NodeBinding<BoundPlanner> binding() {
  using N = BoundPlanner;
  using runtime::Outbox;
  runtime::NodeBinding<N> b;
  b.name = "planner";
  b.inputs = {
      runtime::input<robot_pose_t, N>(channels::kRobotPose,
                                      [](N& n, const robot_pose_t& m, Outbox&) { n.node.onPose(m); }),
      runtime::input<tracked_objects_t, N>(channels::kPerceptionObjects,
                                           [](N& n, const tracked_objects_t& m, Outbox&) { n.node.onObjects(m); }),
      runtime::input<static_points_t, N>(channels::kPerceptionStatic,
                                         [](N& n, const static_points_t& m, Outbox&) { n.node.onStatic(m); }),
      runtime::input<nav_goal_t, N>(channels::kNavGoal,
                                    [](N& n, const nav_goal_t& m, Outbox& out) {
                                      out.log("info", "goal " + std::to_string(m.goal_id) + " (" +
                                                          std::to_string(m.x) + ", " + std::to_string(m.y) + ")");
                                      n.node.onGoal(m);
                                    }),
  };
  b.outputs = {kTrajectoryOutput.channel};
  b.tick_rule = runtime::TickRule::afterInput(10);
  b.tick = [](N& n, int64_t now, Outbox& out) {
    const PlannerOutputs o = n.node.tick(now);
    if (o.plan) ++n.plan_cycles;
    if (o.trajectory) out.publish(kTrajectoryOutput, *o.trajectory);
    if (o.plan && o.plan->message != n.last_message) {
      if (!o.plan->message.empty()) out.log(o.plan->result == PlanResult::kOk ? "info" : "warn", o.plan->message);
      n.last_message = o.plan->message;
    }
  };
  // "Now" is the latest input's utime: the node never reads the wall clock.
  b.clock = [](const N& n) { return n.node.clock().now(); };
  b.status_channel = channels::kPlannerStatus;
  b.status = [](N& n) -> StatusReport& { return n.status; };
  return b;
}

}  // namespace planner
}  // namespace ucon
