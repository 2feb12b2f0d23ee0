// What a planning cycle publishes (PLANNER_TRAJECTORY) and reports (PLANNER_STATUS).
#include <cmath>
#include <limits>

#include "ucon/planner/planner_node.hpp"

namespace ucon::planner {

const char* toString(PlanResult r) {
  switch (r) {
    case PlanResult::kOk: return "ok";
    case PlanResult::kGoalReached: return "goal reached";
    case PlanResult::kStopNoFeasible: return "no feasible trajectory: stopping";
    case PlanResult::kStopNoPose: return "no valid pose: stopping";
    case PlanResult::kStopNoMap: return "no static map yet: stopping";
    case PlanResult::kStopStaleObjects: return "moving obstacles stale or missing: stopping";
    case PlanResult::kCancelled: return "goal cancelled: stopping";
    case PlanResult::kKeptPrevious: return "new plan failed its check: keeping the previous one";
  }
  return "unknown";
}

trajectory_t PlannerNode::finish(const trajectory::PiecewisePolynomial& pp, int64_t now, int8_t status,
                                 const std::string& message) {
  trajectory_t msg{};
  pp.toMessage(&msg);
  msg.utime = now;
  msg.seq = ++seq_;
  msg.plan_id = ++plan_id_;
  msg.goal_id = goal_ ? goal_->goal_id : 0;
  msg.status = status;
  msg.message = message;
  msg.yaw = (goal_ && std::isfinite(goal_->yaw)) ? goal_->yaw : std::numeric_limits<double>::quiet_NaN();
  current_ = pp;
  current_msg_ = msg;
  current_status_ = status;
  return msg;
}

trajectory_t PlannerNode::resend(int64_t now, const std::string& message) {
  current_msg_.utime = now;
  current_msg_.seq = ++seq_;
  current_msg_.message = message;
  return current_msg_;  // same plan_id: the controller keeps following the same curve
}

trajectory_t PlannerNode::stopTrajectory(int64_t now, int8_t status, const std::string& message) {
  trajectory::PiecewisePolynomial pp;
  if (stopPolynomial(now, &pp)) return finish(pp, now, status, message);
  trajectory_t msg{};
  msg.utime = now;
  msg.seq = ++seq_;
  msg.plan_id = ++plan_id_;
  msg.goal_id = goal_ ? goal_->goal_id : 0;
  msg.status = trajectory_t::STATUS_INVALID;
  msg.message = message.empty() ? "no state to stop from" : message;
  msg.dim = 2;
  msg.order1 = 6;
  msg.yaw = std::numeric_limits<double>::quiet_NaN();
  current_ = trajectory::PiecewisePolynomial();
  current_msg_ = msg;
  current_status_ = msg.status;
  return msg;
}

void PlannerNode::record(const PlanInfo& info) {
  report_.count("plans");
  report_.count(std::string("result_") + [&] {
    switch (info.result) {
      case PlanResult::kOk: return "ok";
      case PlanResult::kGoalReached: return "goal_reached";
      case PlanResult::kStopNoFeasible: return "stop_no_feasible";
      case PlanResult::kStopNoPose: return "stop_no_pose";
      case PlanResult::kStopNoMap: return "stop_no_map";
      case PlanResult::kStopStaleObjects: return "stop_stale_objects";
      case PlanResult::kCancelled: return "cancelled";
      case PlanResult::kKeptPrevious: return "kept_previous";
    }
    return "unknown";
  }());
  report_.time("map", info.map_ms);
  report_.time("front_end", info.front_end_ms);
  report_.time("optimize", info.optimize_ms);
  report_.time("check", info.check_ms);
  report_.time("plan_total", info.total_ms);
  report_.set("result", double(int(info.result)));
  report_.set("iterations", info.iterations);
  report_.set("cost_total", info.cost_total);
  report_.set("cost_energy", info.cost_energy);
  report_.set("cost_time", info.cost_time);
  report_.set("cost_static", info.cost_static);
  report_.set("cost_dynamic", info.cost_dynamic);
  report_.set("cost_feasibility", info.cost_feasibility);
  switch (info.result) {
    case PlanResult::kOk:
    case PlanResult::kGoalReached:
    case PlanResult::kKeptPrevious:
      if (info.guide == GuideStatus::kOk) {
        report_.setHealth(process_status_t::HEALTH_OK, "");
      } else {
        report_.setHealth(process_status_t::HEALTH_WARN, toString(info.guide));
      }
      break;
    case PlanResult::kCancelled:
      report_.setHealth(info.message == "goal cancelled" ? process_status_t::HEALTH_OK
                                                         : process_status_t::HEALTH_WARN,
                        info.message == "goal cancelled" ? "" : info.message);
      break;
    default:
      // Holding at the nearest reachable point of a blocked goal is a warning, not a fault.
      report_.setHealth(info.guide == GuideStatus::kGoalInCollision || info.guide == GuideStatus::kGoalUnreachable
                            ? process_status_t::HEALTH_WARN
                            : process_status_t::HEALTH_ERROR,
                        info.message);
  }
}

}  // namespace ucon::planner
