// ucon-simulator: the simulated robot hardware. Emulates the Livox Mid-360 on UDP (point and
// IMU packets, control acks) and the Mecanum base (BASE_WHEEL_CMD in; ROBOT_POSE,
// SIM_GROUND_TRUTH, SIM_STATUS out), advancing simulation time at --rate x real time.
#include <CLI/CLI.hpp>

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "src/udp.hpp"
#include "ucon/channels.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/simulator/scenario_loader.hpp"
#include "ucon/simulator/simulator.hpp"
#include "ucon/world/difficulty.hpp"

namespace {

constexpr const char* kName = "simulator";

bool isDir(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ucon;
  CLI::App app{"Simulated robot: Livox Mid-360 over UDP + Mecanum base over LCM."};
  std::string config_path = "deploy/config/simulator.yaml", scenario_spec = "pedestrians", url, scenario_dir;
  double rate = 1.0, duration = 0.0;
  long long seed = -1;
  app.add_option("--config", config_path, "simulator config (YAML)");
  app.add_option("--scenario", scenario_spec, "pedestrians | crossing | bench:<N_d>:<seed> | path.yaml");
  app.add_option("--rate", rate, "simulation speed, 1.0 = real time")->check(CLI::Range(0.01, 100.0));
  app.add_option("--duration", duration, "stop after this much simulation time [s]; 0 = run until stopped")
      ->check(CLI::Range(0.0, 1e7));
  app.add_option("--seed", seed, "override the scenario seed (pedestrian timelines / bench generator)")
      ->check(CLI::Range(0LL, 9000000000000000000LL));
  app.add_option("--scenario-dir", scenario_dir, "folder of the named scenarios (default deploy/scenarios)");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  std::string pose_source;
  app.add_option("--pose-source", pose_source, "override the config's pose_source: ground_truth | none")
      ->check(CLI::IsMember({"ground_truth", "none"}));
  CLI11_PARSE(app, argc, argv);

  auto params = runtime::loadConfigFile<simulator::SimulatorParams>(kName, config_path);
  if (!params) return 2;
  if (!pose_source.empty()) params->pose_source = pose_source;
  if (const std::string bad = params->validate(); !bad.empty()) {
    runtime::logLine(kName, "error", "config " + config_path + ": " + bad);
    return 2;
  }
  if (scenario_dir.empty()) scenario_dir = isDir("deploy/scenarios") ? "deploy/scenarios" : UCON_SCENARIO_DIR;
  std::string err;
  auto scenario = simulator::loadScenario(scenario_spec, scenario_dir, seed, runtime::readTextFile, &err);
  if (!scenario) {
    runtime::logLine(kName, "error", err);
    return 2;
  }
  const auto host_ip = livox::parseIpv4(params->net.host_ip);
  const auto sensor_ip = livox::parseIpv4(params->net.sensor_ip);
  if (!host_ip || !sensor_ip) {
    runtime::logLine(kName, "error", "config " + config_path + ": net.host_ip / net.sensor_ip must be IPv4 addresses");
    return 2;
  }

  simulator::Simulator sim(*params, *scenario);
  world::DifficultyCounts difficulty;
  bool have_difficulty = false;
  {
    // How hard is it for perception? Counted from ground truth (only for small scenes: the
    // count is quadratic in the number of movers).
    if (scenario->movers.size() <= 20) {
      const auto& mount = params->lidar.mount_xyz;
      const world::Vec3 sensor(scenario->robot.start.x() + mount[0], scenario->robot.start.y() + mount[1], mount[2]);
      difficulty = world::computeDifficulty(sim.world(), sensor, scenario->duration_s);
      have_difficulty = true;
      runtime::logLine(kName, "info", "scenario " + scenario->name + " (seed " + std::to_string(scenario->seed) +
                                          ") difficulty from ground truth: " + difficulty.toString());
    }
    runtime::logLine(kName, "info",
                     "scenario " + scenario->name + ": " + std::to_string(scenario->statics.size()) +
                         " static, " + std::to_string(scenario->movers.size()) + " moving obstacles, duration " +
                         std::to_string(scenario->duration_s) + " s");
  }

  // Sockets of the emulated sensors: control (discovery, commands) and data senders.
  std::vector<std::array<uint8_t, 4>> sensor_ips = {*sensor_ip};
  for (const auto& e : params->extra_lidars) {
    const auto ip = livox::parseIpv4(e.sensor_ip);
    if (!ip) {
      runtime::logLine(kName, "error", "config " + config_path + ": extra_lidars sensor_ip '" + e.sensor_ip +
                                           "' is not an IPv4 address");
      return 2;
    }
    sensor_ips.push_back(*ip);
  }
  simulator::SensorSockets sensors;
  {
    simulator::SensorSockets::Ports ports;
    ports.discovery = static_cast<uint16_t>(params->net.discovery_port);
    ports.command = static_cast<uint16_t>(params->net.command_port);
    ports.point = static_cast<uint16_t>(params->net.point_src_port);
    ports.imu = static_cast<uint16_t>(params->net.imu_src_port);
    std::string warn;
    if (!sensors.open(sensor_ips, ports, &err, &warn)) {
      runtime::logLine(kName, "error", err);
      return 1;
    }
    if (!warn.empty()) runtime::logLine(kName, "warn", warn);
  }

  runtime::installSignalHandlers();
  auto rt = runtime::NodeRuntime::open(kName, url, &err);
  if (!rt) {
    runtime::logLine(kName, "error", err);
    return 1;
  }
  StatusReport status(kName);
  rt->subscribe<wheel_cmd_t>(channels::kBaseWheelCmd,
                             [&](const wheel_cmd_t& c, const std::string&) {
                               if (!sim.onWheelCmd(c)) status.count("bad_wheel_cmds");
                             });
  rt->setStatus(channels::kSimStatus, params->status_period_s, [&]() -> StatusReport& { return status; },
                [&] { return sim.utime(); });

  using Clock = std::chrono::steady_clock;
  auto wall0 = Clock::now();
  int64_t sim0 = sim.utime();
  const int64_t end_utime = duration > 0 ? params->start_utime + static_cast<int64_t>(std::llround(duration * 1e6)) : 0;
  simulator::SimOutputs out;
  int64_t send_errors = 0, overruns = 0;

  runtime::logLine(kName, "info", "running at " + std::to_string(rate) + "x real time; points -> " +
                                      params->net.host_ip + ":" + std::to_string(params->net.host_point_port) +
                                      ", IMU -> :" + std::to_string(params->net.host_imu_port));
  const int rc = rt->spin(1, [&] {
    send_errors += sensors.serviceControl(
        [&](std::size_t i, const uint8_t* data, std::size_t size, bool* broadcast) {
          return sim.control(i).handle(data, size, broadcast);
        });
    const double wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();
    int64_t target = sim0 + static_cast<int64_t>(wall_s * rate * 1e6);
    // Fell far behind (CPU starved, stopped in a debugger): slow down instead of bursting
    // hundreds of packets at once; counted as an overrun.
    if (target - sim.utime() > 250000) {
      ++overruns;
      target = sim.utime() + 20000;
      wall0 = Clock::now();
      sim0 = target;
    }
    if (end_utime > 0 && target >= end_utime) target = end_utime;
    out.clear();
    sim.advanceTo(target, out);
    for (const auto& d : out.point_packets)
      if (!sensors.send(d.sensor, false, d.bytes.data(), d.bytes.size(), d.ip, d.port)) ++send_errors;
    for (const auto& d : out.imu_packets)
      if (!sensors.send(d.sensor, true, d.bytes.data(), d.bytes.size(), d.ip, d.port)) ++send_errors;
    for (const auto& p : out.poses) rt->publish(channels::kRobotPose, p);
    for (const auto& g : out.ground_truth) rt->publish(channels::kSimGroundTruth, g);

    auto& st = status;
    const auto& c = sim.counters();
    st.setCounter("point_packets", c.packets);
    st.setCounter("points", c.points);
    st.setCounter("returns", c.returns);
    st.setCounter("imu_packets", c.imu_packets);
    st.setCounter("poses", c.poses);
    st.setCounter("ground_truth", c.ground_truth);
    st.setCounter("wheel_cmds", c.wheel_cmds);
    st.setCounter("cmd_timeouts", c.cmd_timeouts);
    st.setCounter("collisions", c.collision_episodes);
    st.setCounter("send_errors", send_errors);
    st.setCounter("encode_errors", c.encode_errors);
    st.setCounter("realtime_overruns", overruns);
    st.setCounter("control_requests", sim.control().counters().requests);
    st.setCounter("control_malformed", sim.control().counters().malformed);
    st.set("sim_time_s", sim.simTime());
    st.set("min_clearance_m", std::isfinite(sim.minClearance()) ? sim.minClearance() : -1.0);
    st.set("sampling", sim.control().state().sampling() ? 1.0 : 0.0);
    if (have_difficulty) {
      st.set("scenario_close_passes", difficulty.close_passes);
      st.set("scenario_static_passes", difficulty.static_passes);
      st.set("scenario_occlusions", difficulty.occlusions);
    }
    if (send_errors > 0)
      st.setHealth(process_status_t::HEALTH_WARN, "UDP send errors");
    if (end_utime > 0 && sim.utime() >= end_utime) runtime::requestExit();
  });
  rt->publishStatus();
  const auto& c = sim.counters();
  runtime::logLine(kName, "info",
                   "stopped at t = " + std::to_string(sim.simTime()) + " s: " + std::to_string(c.packets) +
                       " point packets, " + std::to_string(c.imu_packets) + " IMU packets, " +
                       std::to_string(c.collision_episodes) + " collisions, " + std::to_string(send_errors) +
                       " send errors");
  return rc;
}
