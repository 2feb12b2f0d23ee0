// ucon-odometry: LIDAR_IMU + LIDAR_POINTS -> ROBOT_POSE (every IMU sample), ODOMETRY_STATUS
// (every frame), ODOMETRY_HEALTH (1 Hz). Thin main: flags, config (and the start pose), LCM;
// the wiring is the node's binding, the logic OdometryNode around ucon::lio::LioOdometry.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "ucon/odometry/binding.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/simulator/scenario_loader.hpp"

namespace {
constexpr const char* kName = "odometry";

bool parsePose(const std::string& s, Eigen::Vector3d* out) {
  std::stringstream ss(s);
  std::string item;
  double v[3];
  int n = 0;
  while (std::getline(ss, item, ',') && n < 3) {
    try {
      std::size_t used = 0;
      v[n] = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(v[n])) return false;
    } catch (...) {
      return false;
    }
    ++n;
  }
  if (n != 3 || std::getline(ss, item, ',')) return false;
  *out = Eigen::Vector3d(v[0], v[1], v[2]);
  return true;
}
}  // namespace

int main(int argc, char** argv) {
  using ucon::runtime::logLine;
  CLI::App app{"UCON LiDAR-inertial odometry: the robot's pose from the Mid-360's points and IMU."};
  std::string config_path = "deploy/config/odometry.yaml", url, initial_pose, scenario_spec, scenario_dir;
  app.add_option("--config", config_path, "YAML config (deploy/config/odometry.yaml)");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--initial-pose", initial_pose,
                 "X,Y,YAW: where the base stands at start [m, m, rad] (overrides init.pose)");
  app.add_option("--scenario", scenario_spec,
                 "take the start pose from a simulator scenario (pedestrians | crossing | bench:<N_d>:<seed> | path.yaml)");
  app.add_option("--scenario-dir", scenario_dir, "folder of the named scenarios (default deploy/scenarios)");
  bool print_start = false;
  app.add_flag("--print-start-pose", print_start,
               "print the start pose as 'X, Y, YAW' (after --scenario / --initial-pose) and exit");
  CLI11_PARSE(app, argc, argv);

  auto params = ucon::runtime::loadConfigFile<ucon::odometry::OdometryParams>(kName, config_path);
  if (!params) return 2;
  if (!scenario_spec.empty()) {
    std::string err;
    if (scenario_dir.empty()) scenario_dir = UCON_SCENARIO_DIR;
    const auto sc = ucon::simulator::loadScenario(scenario_spec, scenario_dir, -1, ucon::runtime::readTextFile, &err);
    if (!sc) {
      logLine(kName, "error", err);
      return 2;
    }
    params->lio.initial_pose = Eigen::Vector3d(sc->robot.start.x(), sc->robot.start.y(), sc->robot.start_yaw);
  }
  if (!initial_pose.empty() && !parsePose(initial_pose, &params->lio.initial_pose)) {
    logLine(kName, "error", "--initial-pose '" + initial_pose + "': expected X,Y,YAW (three numbers)");
    return 2;
  }
  if (const std::string bad = params->validate(); !bad.empty()) {
    logLine(kName, "error", config_path + ": " + bad);
    return 2;
  }
  if (print_start) {
    const Eigen::Vector3d& p = params->lio.initial_pose;
    std::printf("%.17g, %.17g, %.17g\n", p.x(), p.y(), p.z());
    return 0;
  }

  std::string err;
  auto io = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!io) {
    logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();
  ucon::odometry::BoundOdometry node(*params);
  const Eigen::Vector3d& p0 = params->lio.initial_pose;
  char start[160];
  std::snprintf(start, sizeof(start), "running (start pose %.2f, %.2f m, yaw %.3f rad; poses on %s; LCM %s)", p0.x(),
                p0.y(), p0.z(), params->pose_channel.c_str(), io->url().c_str());
  logLine(kName, "info", start);
  return io->run(ucon::odometry::binding(*params), node);
}
