// ucon-base-controller: trajectory + pose -> Mecanum wheel commands (BASE_WHEEL_CMD or a motor
// board on a serial line), BASE_STATUS and BASE_CONTROLLER_STATUS. Thin main: flags, config,
// LCM, the motor backend; the wiring and the control tick are the node's binding.
#include <CLI/CLI.hpp>

#include <memory>

#include "ucon/base_controller/binding.hpp"
#include "ucon/base_controller/motor_backend.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace bc = ucon::base_controller;
namespace rt = ucon::runtime;

int main(int argc, char** argv) {
  const std::string name = "base_controller";
  CLI::App app{"Mecanum base controller: follows PLANNER_TRAJECTORY using ROBOT_POSE."};
  std::string config_path, url, backend_type, serial_device, clock_mode = "live";
  app.add_option("--config", config_path, "YAML config (deploy/config/base_controller.yaml)")
      ->required();
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--backend", backend_type, "motor backend, overrides backend.type")
      ->check(CLI::IsMember({"lcm", "serial"}));
  app.add_option("--serial-device", serial_device, "motor board tty, overrides backend.serial_device");
  app.add_option("--clock", clock_mode,
                 "live: control.rate_hz on a wall timer, time extrapolated from messages; "
                 "message: ticks on message time only (replay)")
      ->check(CLI::IsMember({"live", "message"}));
  CLI11_PARSE(app, argc, argv);

  auto params = rt::loadConfigFile<bc::BaseControllerParams>(name, config_path);
  if (!params) return 2;
  if (!backend_type.empty()) params->backend.type = backend_type;
  if (!serial_device.empty()) params->backend.serial_device = serial_device;
  if (const std::string err = params->validate(); !err.empty()) {
    rt::logLine(name, "error", "config: " + err);
    return 2;
  }

  std::string err;
  auto io = rt::NodeRuntime::open(name, url, &err);
  if (!io) {
    rt::logLine(name, "error", err);
    return 1;
  }
  std::unique_ptr<bc::MotorBackend> backend;
  if (params->backend.type == "serial") {
    auto port = bc::SerialPort::open(params->backend.serial_device, params->backend.serial_baud, &err);
    if (!port) {
      rt::logLine(name, "error", "serial backend: " + err);
      return 1;
    }
    backend = std::make_unique<bc::SerialMotorBackend>(std::move(port), params->mecanum);
  } else {
    backend = std::make_unique<bc::LcmMotorBackend>(io->lcm(), ucon::channels::kBaseWheelCmd);
  }
  // Wheel commands go to the backend (which counts what it sent), not straight to LCM.
  io->outbox().divert(bc::kWheelCmdOutput, [&](const ucon::wheel_cmd_t& c) { backend->send(c); });
  io->addStatus([&](ucon::StatusReport& st) {
    for (const auto& [counter, value] : backend->counters()) st.setCounter(counter, value);
  });

  bc::BoundBaseController controller(*params);
  rt::RunOptions options;
  options.message_clock = clock_mode == "message";
  rt::installSignalHandlers();
  rt::logLine(name, "info", "running: backend " + std::string(backend->name()) + ", clock " + clock_mode +
                                ", LCM " + io->url());
  const int rc = io->run(bc::binding(*params), controller, options);

  // Leave the motors braked: a last disabled, zero command.
  backend->send(controller.node.brakeCommand());
  std::string totals;
  for (const auto& [counter, value] : backend->counters()) totals += " " + counter + "=" + std::to_string(value);
  rt::logLine(name, "info", "stopped;" + totals);
  return rc;
}
