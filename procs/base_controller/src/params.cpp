#include "ucon/base_controller/params.hpp"

#include "ucon/config.hpp"

namespace ucon {
namespace base_controller {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

void ControlParams::read(ConfigReader& r) {
  r.read("rate_hz", rate_hz, 1.0, 1000.0);
  r.read("lead_s", lead_s, 0.0, 0.5);
  r.read("kp_position", kp_position, 0.0, 100.0);
  r.read("kd_velocity", kd_velocity, 0.0, 10.0);
  r.read("accel_feedforward_s", accel_feedforward_s, 0.0, 1.0);
  r.read("max_feedback_speed", max_feedback_speed, 0.0, 10.0);
  r.read("max_speed", max_speed, 1e-3, 10.0);
  r.read("max_linear_accel", max_linear_accel, 1e-3, 100.0);
  r.read("kp_yaw", kp_yaw, 0.0, 100.0);
  r.read("max_yaw_rate", max_yaw_rate, 1e-3, 20.0);
  r.read("max_yaw_accel", max_yaw_accel, 1e-3, 200.0);
}

void HeadingParams::read(ConfigReader& r) {
  r.read("mode", mode, {"hold", "path"});
  r.read("hold_yaw", hold_yaw, -kPi, kPi);
  r.read("min_path_speed", min_path_speed, 0.0, 5.0);
}

void WatchdogParams::read(ConfigReader& r) {
  r.read("pose_timeout_s", pose_timeout_s, 1e-3, 10.0);
  r.read("trajectory_timeout_s", trajectory_timeout_s, 1e-3, 60.0);
  r.read("stop_linear_decel", stop_linear_decel, 1e-3, 100.0);
  r.read("stop_angular_decel", stop_angular_decel, 1e-3, 200.0);
  r.read("max_reference_speed", max_reference_speed, 1e-3, 100.0);
}

void BackendParams::read(ConfigReader& r) {
  r.read("type", type, {"lcm", "serial"});
  r.read("serial_device", serial_device);
  r.read("serial_baud", serial_baud, 9600, 921600);
}

void BaseControllerParams::read(ConfigReader& r) {
  ConfigReader m = r.section("mecanum");
  mecanum.read(m);
  ConfigReader c = r.section("control");
  control.read(c);
  ConfigReader h = r.section("heading");
  heading.read(h);
  ConfigReader w = r.section("watchdog");
  watchdog.read(w);
  ConfigReader b = r.section("backend");
  backend.read(b);
  r.read("status_period_s", status_period_s, 1e-3, 10.0);
  const std::string err = validate();
  if (!err.empty()) {
    const std::size_t colon = err.find(": ");
    if (colon == std::string::npos) {
      r.fail("", err);
    } else {
      r.fail(err.substr(0, colon), err.substr(colon + 2));
    }
  }
}

std::string BaseControllerParams::validate() const {
  const std::string m = mecanum.validate();
  if (!m.empty()) return "mecanum." + m;
  if (heading.mode != "hold" && heading.mode != "path") {
    return "heading.mode: must be \"hold\" or \"path\"";
  }
  if (backend.type != "lcm" && backend.type != "serial") {
    return "backend.type: must be \"lcm\" or \"serial\"";
  }
  if (backend.type == "serial" && backend.serial_device.empty()) {
    return "backend.serial_device: must name a tty for the serial backend";
  }
  return {};
}

}  // namespace base_controller
}  // namespace ucon
