// ucon-base-controller: trajectory + pose -> Mecanum wheel commands (BASE_WHEEL_CMD or a motor
// board on a serial line), BASE_STATUS and BASE_CONTROLLER_STATUS. All logic is in
// BaseController; this file wires it to LCM, the motor backend and the control timer.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <memory>

#include "ucon/base_controller/control_timer.hpp"
#include "ucon/base_controller/controller.hpp"
#include "ucon/base_controller/motor_backend.hpp"
#include "ucon/channels.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace bc = ucon::base_controller;
namespace rt = ucon::runtime;

namespace {
constexpr const char* kName = "base_controller";
}

int main(int argc, char** argv) {
  CLI::App app{"Mecanum base controller: follows PLANNER_TRAJECTORY using ROBOT_POSE."};
  std::string config_path, url, backend_type, serial_device, clock_mode = "live";
  app.add_option("--config", config_path, "YAML config (deploy/config/base_controller.yaml)")
      ->required();
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--backend", backend_type, "motor backend, overrides backend.type")
      ->check(CLI::IsMember({"lcm", "serial"}));
  app.add_option("--serial-device", serial_device, "motor board tty, overrides backend.serial_device");
  app.add_option("--clock", clock_mode,
                 "live: 100 Hz on a wall timer, time extrapolated from messages; "
                 "message: ticks on message time only (replay)")
      ->check(CLI::IsMember({"live", "message"}));
  CLI11_PARSE(app, argc, argv);

  auto params = rt::loadConfigFile<bc::BaseControllerParams>(kName, config_path);
  if (!params) return 2;
  if (!backend_type.empty()) params->backend.type = backend_type;
  if (!serial_device.empty()) params->backend.serial_device = serial_device;
  if (const std::string err = params->validate(); !err.empty()) {
    rt::logLine(kName, "error", "config: " + err);
    return 2;
  }

  std::string err;
  auto node_rt = rt::NodeRuntime::open(kName, url, &err);
  if (!node_rt) {
    rt::logLine(kName, "error", err);
    return 1;
  }

  std::unique_ptr<bc::MotorBackend> backend;
  if (params->backend.type == "serial") {
    auto port = bc::SerialPort::open(params->backend.serial_device, params->backend.serial_baud, &err);
    if (!port) {
      rt::logLine(kName, "error", "serial backend: " + err);
      return 1;
    }
    backend = std::make_unique<bc::SerialMotorBackend>(std::move(port), params->mecanum);
  } else {
    backend = std::make_unique<bc::LcmMotorBackend>(node_rt->lcm(), ucon::channels::kBaseWheelCmd);
  }

  bc::BaseController node(*params);
  bc::ControlTimer timer(clock_mode == "live" ? bc::ControlTimer::Mode::kLive
                                              : bc::ControlTimer::Mode::kMessage,
                         params->control.rate_hz);
  int8_t last_logged_state = -1;
  auto emit = [&](const bc::BaseControllerOutput& out) {
    if (out.wheel_cmd) backend->send(*out.wheel_cmd);
    if (out.status) {
      node_rt->publish(ucon::channels::kBaseStatus, *out.status);
      if (out.status->state != last_logged_state) {
        last_logged_state = out.status->state;
        rt::logLine(kName, "info", "state " + std::to_string(out.status->state) +
                                      (out.status->reason.empty() ? "" : ": " + out.status->reason));
      }
    }
  };
  // Live: handle the message, then anchor the timer on its utime and arrival (wall) time.
  // Message clock: first run the ticks before this message's time, then handle it (see
  // ControlTimer), so a replayed log gives the same commands as LockstepReplay.
  const bool message_clock = clock_mode == "message";
  auto onMessage = [&](int64_t msg_utime, const auto& handle) {
    if (message_clock) {
      timer.observe(msg_utime, rt::wallUtime());
      for (int64_t t : timer.due(rt::wallUtime())) emit(node.tick(t));
      emit(handle());
    } else {
      emit(handle());
      timer.observe(msg_utime, rt::wallUtime());
    }
  };
  node_rt->subscribe<ucon::robot_pose_t>(
      ucon::channels::kRobotPose, [&](const ucon::robot_pose_t& m, const std::string&) {
        onMessage(m.utime, [&] { return node.onPose(m); });
      });
  node_rt->subscribe<ucon::trajectory_t>(
      ucon::channels::kPlannerTrajectory, [&](const ucon::trajectory_t& m, const std::string&) {
        onMessage(m.utime, [&] { return node.onTrajectory(m); });
      });
  node_rt->subscribe<ucon::estop_t>(
      ucon::channels::kBaseEstop, [&](const ucon::estop_t& m, const std::string&) {
        onMessage(m.utime, [&] { return node.onEstop(m); });
      });
  node_rt->setStatusChannel(ucon::channels::kBaseControllerStatus, 1.0, [&] { return node.now(); });

  rt::installSignalHandlers();
  rt::logLine(kName, "info", "running: backend " + std::string(backend->name()) + ", clock " +
                                 clock_mode + ", LCM " + node_rt->url());
  int64_t next_status_wall = rt::wallUtime() + 1000000;
  int rc = 0;
  // The one loop shape: wait for a message or the next control deadline, then tick.
  while (!rt::exitRequested()) {
    int timeout_ms = 100;
    if (clock_mode == "live" && timer.nextWallDeadline() > 0) {
      const int64_t wait_us = timer.nextWallDeadline() - rt::wallUtime();
      timeout_ms = static_cast<int>(std::clamp<int64_t>((wait_us + 999) / 1000, 0, 100));
    }
    if (node_rt->handleOnce(timeout_ms) < 0) {
      if (rt::exitRequested()) break;  // the signal interrupted the wait (EINTR): clean exit
      rt::logLine(kName, "error", "LCM stopped working; exiting");
      rc = 1;
      break;
    }
    for (int64_t t : timer.due(rt::wallUtime())) emit(node.tick(t));

    const int64_t wall = rt::wallUtime();
    if (wall >= next_status_wall) {
      next_status_wall = wall + 1000000;
      ucon::StatusReport& st = node_rt->status();
      for (const auto& [name, value] : node.counters()) st.setCounter(name, value);
      for (const auto& [name, value] : backend->counters()) st.setCounter(name, value);
      st.setCounter("ticks_skipped", timer.skippedTicks());
      st.set("state", node.state());
      if (node.state() == ucon::base_status_t::STATE_TRACKING ||
          node.state() == ucon::base_status_t::STATE_IDLE) {
        st.setHealth(ucon::process_status_t::HEALTH_OK, "");
      } else {
        st.setHealth(ucon::process_status_t::HEALTH_WARN, node.reason());
      }
      node_rt->publishStatus();
    }
  }
  // Leave the motors braked: a last disabled, zero command.
  backend->send(node.brakeCommand());
  std::string totals;
  for (const auto& [name, value] : backend->counters()) totals += " " + name + "=" + std::to_string(value);
  rt::logLine(kName, "info", "stopped;" + totals);
  return rc;
}
