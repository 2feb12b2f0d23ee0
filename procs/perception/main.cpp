// ucon-perception: LIDAR_POINTS + ROBOT_POSE -> PERCEPTION_OBJECTS, PERCEPTION_STATIC,
// PERCEPTION_STATUS. Thin main: flags, config, LCM; the wiring is the node's binding.
#include <CLI/CLI.hpp>

#include "ucon/perception/binding.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace rt = ucon::runtime;

int main(int argc, char** argv) {
  const auto binding = ucon::perception::binding();
  CLI::App app{"UCON perception: tracked dynamic objects with covariance and static points."};
  std::string config_path = "deploy/config/perception.yaml";
  std::string url;
  std::string association;
  app.add_option("--config", config_path, "YAML config (deploy/config/perception.yaml)");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--association", association, "override the config's association method")
      ->check(CLI::IsMember({"ucon", "fapp"}));
  CLI11_PARSE(app, argc, argv);

  auto params = rt::loadConfigFile<ucon::perception::PerceptionParams>(binding.name, config_path);
  if (!params) return 2;
  if (!association.empty()) params->association = association;

  std::string err;
  auto io = rt::NodeRuntime::open(binding.name, url, &err);
  if (!io) {
    rt::logLine(binding.name, "error", err);
    return 1;
  }
  rt::installSignalHandlers();
  ucon::perception::PerceptionNode node(*params);
  rt::logLine(binding.name, "info", "running (association: " + params->association + ", LCM " + io->url() + ")");
  return io->run(binding, node);
}
