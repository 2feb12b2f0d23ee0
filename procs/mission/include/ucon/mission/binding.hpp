#pragma once
/// @file binding.hpp
/// ucon-mission's wiring (see ucon/runtime/binding.hpp): ROBOT_POSE (which may send the next
/// NAV_GOAL), SIM_GROUND_TRUTH, PERCEPTION_OBJECTS, PLANNER_STATUS and PROC_STATUS in; NAV_GOAL
/// out; no tick; the process ends when the mission is done. It keeps score rather than
/// reporting a status of its own.

#include "ucon/channels.hpp"
#include "ucon/mission/mission_node.hpp"
#include "ucon/runtime/binding.hpp"

namespace ucon {
namespace mission {

inline const runtime::Output<nav_goal_t> kGoalOutput{channels::kNavGoal};

inline runtime::NodeBinding<MissionNode> binding() {
  using N = MissionNode;
  using runtime::Outbox;
  runtime::NodeBinding<N> b;
  b.name = "mission";
  b.inputs = {
      runtime::input<robot_pose_t, N>(channels::kRobotPose,
                                      [](N& n, const robot_pose_t& m, Outbox& out) {
                                        if (auto g = n.onPose(m)) out.publish(kGoalOutput, *g);
                                      }),
      runtime::input<sim_ground_truth_t, N>(channels::kSimGroundTruth,
                                            [](N& n, const sim_ground_truth_t& m, Outbox&) { n.onGroundTruth(m); }),
      runtime::input<tracked_objects_t, N>(channels::kPerceptionObjects,
                                           [](N& n, const tracked_objects_t& m, Outbox&) { n.onObjects(m); }),
      runtime::input<process_status_t, N>(channels::kPlannerStatus,
                                          [](N& n, const process_status_t& m, Outbox&) { n.onPlannerStatus(m); }),
      runtime::input<supervisor_status_t, N>(channels::kProcStatus,
                                             [](N& n, const supervisor_status_t& m, Outbox&) { n.onProcStatus(m); }),
  };
  b.outputs = {kGoalOutput.channel};
  b.tick_rule = runtime::TickRule::none(50);
  b.done = [](const N& n) { return n.done(); };
  return b;
}

}  // namespace mission
}  // namespace ucon
