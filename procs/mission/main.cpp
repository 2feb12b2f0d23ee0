// ucon-mission: drives a simulated run — sends the scenario's goals on NAV_GOAL one after
// another, prints a live status line, and at the end a summary (goals, collisions, clearance,
// speed, MOTA against ground truth, CPU per process); exits 0 on success, 1 otherwise.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>

#include "ucon/mission/binding.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/simulator/scenario_loader.hpp"

int main(int argc, char** argv) {
  using ucon::runtime::logLine;
  const std::string kName = "mission";
  CLI::App app{"Send a scenario's goals, watch the run, print a summary."};
  std::string config = "deploy/config/mission.yaml", scenario_spec = "pedestrians", scenario_dir,
              url, summary_json;
  double duration = 0.0;
  bool loop = false;
  app.add_option("--config", config, "mission YAML config");
  app.add_option("--scenario", scenario_spec, "pedestrians | crossing | bench:<N_d>:<seed> | path.yaml");
  app.add_option("--scenario-dir", scenario_dir, "folder of the named scenarios (default deploy/scenarios)");
  app.add_option("--duration", duration, "end after this much simulated time [s]; 0 = when the goals are reached")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--loop", loop,
               "after the last goal, back to the start and through the goals again, until --duration");
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
  auto io = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!io) {
    logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();

  ucon::mission::MissionNode node(*params, scenario->robot.goals, duration, loop);
  std::printf("mission: scenario %s, %zu goal(s)%s%s\n", scenario->name.c_str(),
              scenario->robot.goals.size(), loop ? " in a loop (back to the start after the last)" : "",
              duration > 0 ? (", at most " + std::to_string(static_cast<int>(duration)) + " s").c_str() : "");
  std::fflush(stdout);
  // A live status line every second (wall time: it is for the person watching).
  ucon::runtime::RunOptions options;
  auto next_line = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  options.after_tick = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_line) {
      std::printf("%s\n", node.statusLine().c_str());
      std::fflush(stdout);
      next_line = now + std::chrono::seconds(1);
    }
  };
  io->run(ucon::mission::binding(), node, options);
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
