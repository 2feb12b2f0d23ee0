// ucon-mission: drives a simulated run — sends the scenario's goals on NAV_GOAL one after
// another, prints a live status line, and at the end a summary (goals, collisions, clearance,
// speed, MOTA against ground truth, CPU per process); exits 0 on success, 1 otherwise.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>

#include "ucon/channels.hpp"
#include "ucon/mission/mission_node.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/simulator/scenario_loader.hpp"

int main(int argc, char** argv) {
  using ucon::runtime::logLine;
  constexpr const char* kName = "mission";
  CLI::App app{"Send a scenario's goals, watch the run, print a summary."};
  std::string config = "deploy/config/mission.yaml", scenario_spec = "pedestrians", scenario_dir,
              url, summary_json;
  double duration = 0.0;
  app.add_option("--config", config, "mission YAML config");
  app.add_option("--scenario", scenario_spec, "pedestrians | crossing | bench:<N_d>:<seed> | path.yaml");
  app.add_option("--scenario-dir", scenario_dir, "folder of the named scenarios (default deploy/scenarios)");
  app.add_option("--duration", duration, "end after this much simulated time [s]; 0 = when the goals are reached")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--summary-json", summary_json, "also write the summary as JSON to this file");
  app.add_option("--lcm-url", url, "LCM URL");
  CLI11_PARSE(app, argc, argv);

  auto params = ucon::runtime::loadConfigFile<ucon::mission::MissionParams>(kName, config);
  if (!params) return 2;
  if (scenario_dir.empty()) scenario_dir = UCON_SCENARIO_DIR;
  std::string err;
  auto scenario = ucon::simulator::loadScenario(scenario_spec, scenario_dir, -1,
                                                ucon::runtime::readTextFile, &err);
  if (!scenario) {
    logLine(kName, "error", err);
    return 2;
  }
  if (scenario->robot.goals.empty()) {
    logLine(kName, "error", "scenario '" + scenario_spec + "' has no goals");
    return 2;
  }
  auto rt = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!rt) {
    logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();

  ucon::mission::MissionNode node(*params, scenario->robot.goals, duration);
  namespace ch = ucon::channels;
  rt->subscribe<ucon::robot_pose_t>(ch::kRobotPose, [&](const ucon::robot_pose_t& m, const std::string&) {
    if (auto g = node.onPose(m)) rt->publish(ch::kNavGoal, *g);
    if (node.done()) ucon::runtime::requestExit();
  });
  rt->subscribe<ucon::sim_ground_truth_t>(ch::kSimGroundTruth,
      [&](const ucon::sim_ground_truth_t& m, const std::string&) { node.onGroundTruth(m); });
  rt->subscribe<ucon::tracked_objects_t>(ch::kPerceptionObjects,
      [&](const ucon::tracked_objects_t& m, const std::string&) { node.onObjects(m); });
  rt->subscribe<ucon::process_status_t>(ch::kPlannerStatus,
      [&](const ucon::process_status_t& m, const std::string&) { node.onPlannerStatus(m); });
  rt->subscribe<ucon::supervisor_status_t>(ch::kProcStatus,
      [&](const ucon::supervisor_status_t& m, const std::string&) { node.onProcStatus(m); });

  std::printf("mission: scenario %s, %zu goal(s)%s\n", scenario->name.c_str(),
              scenario->robot.goals.size(),
              duration > 0 ? (", at most " + std::to_string(static_cast<int>(duration)) + " s").c_str() : "");
  std::fflush(stdout);
  auto next_line = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  rt->spin(50, [&] {
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_line) {
      std::printf("%s\n", node.statusLine().c_str());
      std::fflush(stdout);
      next_line = now + std::chrono::seconds(1);
    }
  });
  const std::string reason = node.done() ? node.endReason() : "interrupted";
  const auto summary = node.summary();
  std::printf("%s", ucon::mission::MissionNode::format(summary, reason).c_str());
  std::fflush(stdout);
  if (!summary_json.empty()) {
    std::ofstream out(summary_json);
    out << ucon::mission::MissionNode::toJson(summary, reason) << "\n";
    if (!out) logLine(kName, "error", "cannot write " + summary_json);
  }
  return summary.success() ? 0 : 1;
}
