// ucon-planner: OctoMap ESDF + guide path + sector-MINCO replanning on LCM. Thin main: flags,
// config, LCM; the wiring (ROBOT_POSE, PERCEPTION_OBJECTS, PERCEPTION_STATIC, NAV_GOAL in;
// PLANNER_TRAJECTORY, PLANNER_STATUS out) is the node's binding.
#include <CLI/CLI.hpp>

#include <string>

#include "ucon/planner/binding.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace rt = ucon::runtime;

int main(int argc, char** argv) {
  const auto binding = ucon::planner::binding();
  CLI::App app{"UCON planner: receding-horizon sector-MINCO trajectories (PLANNER_TRAJECTORY)."};
  std::string config_path = "deploy/config/planner.yaml";
  std::string url;
  app.add_option("--config", config_path, "planner YAML config")->check(CLI::ExistingFile);
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  CLI11_PARSE(app, argc, argv);

  auto params = rt::loadConfigFile<ucon::planner::PlannerParams>(binding.name, config_path);
  if (!params) return 2;
  std::string err;
  auto io = rt::NodeRuntime::open(binding.name, url, &err);
  if (!io) {
    rt::logLine(binding.name, "error", err);
    return 1;
  }
  rt::installSignalHandlers();
  ucon::planner::BoundPlanner planner(*params);
  rt::logLine(binding.name, "info", "listening on " + io->url() + ", obstacle model " +
                                        ucon::trajopt::toString(params->optimizer.obstacle_model));
  return io->run(binding, planner);
}
