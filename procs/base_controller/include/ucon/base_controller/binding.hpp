#pragma once
/// @file binding.hpp
/// ucon-base-controller's wiring, used by its main and by its replay adapter (see
/// ucon/runtime/binding.hpp): ROBOT_POSE, PLANNER_TRAJECTORY and BASE_ESTOP to their handlers;
/// the control step ticks at control.rate_hz (live on a wall timer in message time, in replay
/// on the period grid before each message); BASE_WHEEL_CMD (or the motor board: the main
/// diverts it) and BASE_STATUS out; BASE_CONTROLLER_STATUS from the controller's counters.

#include <string>

#include "ucon/base_controller/controller.hpp"
#include "ucon/channels.hpp"
#include "ucon/runtime/binding.hpp"

namespace ucon {
namespace base_controller {

/// The controller as its harnesses run it, with its status report and the last state logged.
struct BoundBaseController {
  explicit BoundBaseController(const BaseControllerParams& params) : node(params) {}
  BaseController node;
  StatusReport status{"base_controller"};
  int8_t logged_state = -1;
};

inline const runtime::Output<ucon::wheel_cmd_t> kWheelCmdOutput{channels::kBaseWheelCmd};
inline const runtime::Output<ucon::base_status_t> kBaseStatusOutput{channels::kBaseStatus};

/// Publishes the wheel command, then the status (logging each change of state).
inline void publish(BoundBaseController& n, const BaseControllerOutput& o, runtime::Outbox& out) {
  if (o.wheel_cmd) out.publish(kWheelCmdOutput, *o.wheel_cmd);
  if (o.status) {
    out.publish(kBaseStatusOutput, *o.status);
    if (o.status->state != n.logged_state) {
      n.logged_state = o.status->state;
      out.log("info", "state " + std::to_string(o.status->state) +
                          (o.status->reason.empty() ? "" : ": " + o.status->reason));
    }
  }
}

inline runtime::NodeBinding<BoundBaseController> binding(const BaseControllerParams& params) {
  using N = BoundBaseController;
  using runtime::Outbox;
  runtime::NodeBinding<N> b;
  b.name = "base_controller";
  b.inputs = {
      runtime::input<ucon::robot_pose_t, N>(channels::kRobotPose, [](N& n, const ucon::robot_pose_t& m, Outbox& out) {
        publish(n, n.node.onPose(m), out);
      }),
      runtime::input<ucon::trajectory_t, N>(channels::kPlannerTrajectory,
                                            [](N& n, const ucon::trajectory_t& m, Outbox& out) {
                                              publish(n, n.node.onTrajectory(m), out);
                                            }),
      runtime::input<ucon::estop_t, N>(channels::kBaseEstop, [](N& n, const ucon::estop_t& m, Outbox& out) {
        publish(n, n.node.onEstop(m), out);
      }),
  };
  b.outputs = {kWheelCmdOutput.channel, kBaseStatusOutput.channel};
  b.tick_rule = runtime::TickRule::periodic(params.control.rate_hz);
  b.tick = [](N& n, int64_t t, Outbox& out) { publish(n, n.node.tick(t), out); };
  b.clock = [](const N& n) { return n.node.now(); };
  b.status_channel = channels::kBaseControllerStatus;
  b.status = [](N& n) -> StatusReport& {
    for (const auto& [name, value] : n.node.counters()) n.status.setCounter(name, value);
    n.status.set("state", n.node.state());
    if (n.node.state() == ucon::base_status_t::STATE_TRACKING || n.node.state() == ucon::base_status_t::STATE_IDLE) {
      n.status.setHealth(ucon::process_status_t::HEALTH_OK, "");
    } else {
      n.status.setHealth(ucon::process_status_t::HEALTH_WARN, n.node.reason());
    }
    return n.status;
  };
  return b;
}

}  // namespace base_controller
}  // namespace ucon
