// ucon-planner: OctoMap ESDF + guide path + sector-MINCO replanning (PlannerNode) on LCM.
// Subscribes ROBOT_POSE, PERCEPTION_OBJECTS, PERCEPTION_STATIC, NAV_GOAL; publishes
// PLANNER_TRAJECTORY and PLANNER_STATUS.
#include <CLI/CLI.hpp>

#include <string>

#include "ucon/channels.hpp"
#include "ucon/planner/planner_node.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

int main(int argc, char** argv) {
  CLI::App app{"UCON planner: receding-horizon sector-MINCO trajectories (PLANNER_TRAJECTORY)."};
  std::string config_path = "deploy/config/planner.yaml";
  std::string url;
  app.add_option("--config", config_path, "planner YAML config")->check(CLI::ExistingFile);
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  CLI11_PARSE(app, argc, argv);

  const char* name = "planner";
  auto params = ucon::runtime::loadConfigFile<ucon::planner::PlannerParams>(name, config_path);
  if (!params) return 2;
  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open(name, url, &err);
  if (!rt) {
    ucon::runtime::logLine(name, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();

  ucon::planner::PlannerNode node(*params, rt->status());
  rt->subscribe<ucon::robot_pose_t>(ucon::channels::kRobotPose,
                                    [&](const ucon::robot_pose_t& m, const std::string&) { node.onPose(m); });
  rt->subscribe<ucon::tracked_objects_t>(
      ucon::channels::kPerceptionObjects,
      [&](const ucon::tracked_objects_t& m, const std::string&) { node.onObjects(m); });
  rt->subscribe<ucon::static_points_t>(
      ucon::channels::kPerceptionStatic,
      [&](const ucon::static_points_t& m, const std::string&) { node.onStatic(m); });
  rt->subscribe<ucon::nav_goal_t>(ucon::channels::kNavGoal, [&](const ucon::nav_goal_t& m, const std::string&) {
    ucon::runtime::logLine(name, "info", "goal " + std::to_string(m.goal_id) + " (" + std::to_string(m.x) +
                                             ", " + std::to_string(m.y) + ")");
    node.onGoal(m);
  });
  rt->setStatusChannel(ucon::channels::kPlannerStatus, 1.0, [&] { return node.clock().now(); });
  ucon::runtime::logLine(name, "info", "listening on " + rt->url() + ", obstacle model " +
                                           ucon::trajopt::toString(params->optimizer.obstacle_model));

  std::string last_message;
  const int rc = rt->spin(10, [&] {
    // "Now" is the latest input's utime: the node never reads the wall clock.
    const auto out = node.tick(node.clock().now());
    if (out.trajectory) rt->publish(ucon::channels::kPlannerTrajectory, *out.trajectory);
    if (out.plan && out.plan->message != last_message) {
      if (!out.plan->message.empty()) {
        ucon::runtime::logLine(name, out.plan->result == ucon::planner::PlanResult::kOk ? "info" : "warn",
                               out.plan->message);
      }
      last_message = out.plan->message;
    }
  });
  return rc;
}
