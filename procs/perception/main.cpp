// ucon-perception: LIDAR_POINTS + ROBOT_POSE -> PERCEPTION_OBJECTS, PERCEPTION_STATIC,
// PERCEPTION_STATUS. Thin main: flags, config, LCM wiring; the logic is PerceptionNode.
#include <CLI/CLI.hpp>

#include <chrono>

#include "ucon/channels.hpp"
#include "ucon/perception/perception_node.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace {
constexpr const char* kName = "perception";
}

int main(int argc, char** argv) {
  CLI::App app{"UCON perception: tracked dynamic objects with covariance and static points."};
  std::string config_path = "deploy/config/perception.yaml";
  std::string url;
  std::string association;
  app.add_option("--config", config_path, "YAML config (deploy/config/perception.yaml)");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--association", association, "override the config's association method")
      ->check(CLI::IsMember({"ucon", "fapp"}));
  CLI11_PARSE(app, argc, argv);

  auto params = ucon::runtime::loadConfigFile<ucon::perception::PerceptionParams>(kName, config_path);
  if (!params) return 2;
  if (!association.empty()) params->association = association;

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!rt) {
    ucon::runtime::logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();
  ucon::perception::PerceptionNode node(*params);

  auto publish = [&](const ucon::perception::PerceptionOutput& out) {
    if (out.objects) rt->publish(ucon::channels::kPerceptionObjects, *out.objects);
    if (out.static_points) rt->publish(ucon::channels::kPerceptionStatic, *out.static_points);
  };
  rt->subscribe<ucon::robot_pose_t>(ucon::channels::kRobotPose,
                                    [&](const ucon::robot_pose_t& p, const std::string&) { node.onPose(p); });
  rt->subscribe<ucon::point_cloud_t>(ucon::channels::kLidarPoints,
                                     [&](const ucon::point_cloud_t& c, const std::string&) {
                                       publish(node.onPoints(c));
                                     });
  ucon::runtime::logLine(kName, "info",
                         "running (association: " + params->association + ", LCM " + rt->url() + ")");
  // PERCEPTION_STATUS once a second (wall time: status is for humans): the node's counters,
  // stage timings and gauges, plus the runtime's decode/publish error counters.
  auto next_status = std::chrono::steady_clock::now();
  const int rc = rt->spin(20, [&] {
    publish(node.tick(node.now()));
    const auto now = std::chrono::steady_clock::now();
    if (now < next_status) return;
    next_status = now + std::chrono::seconds(1);
    for (const char* c : {"decode_errors", "publish_errors"})
      node.status().setCounter(c, rt->status().counter(c));
    rt->publish(ucon::channels::kPerceptionStatus,
                node.status().build(node.now(), ucon::runtime::wallUtime()));
  });
  return rc;
}
