#pragma once
/// @file motor_backend.hpp
/// Where wheel commands go: one interface, two backends. `lcm` publishes BASE_WHEEL_CMD (the
/// simulator's plant listens); `serial` writes the frame of serial_frame.hpp to a motor board.
/// I/O: used by the process, not by the node.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ucon/base_controller/serial_port.hpp"
#include "ucon/mecanum/kinematics.hpp"
#include "ucon/wheel_cmd_t.hpp"

namespace lcm {
class LCM;
}

namespace ucon {
namespace base_controller {

/// Sink for wheel commands.
class MotorBackend {
 public:
  virtual ~MotorBackend() = default;
  /// Sends one command; false if it could not be sent (counted by the backend).
  virtual bool send(const ucon::wheel_cmd_t& cmd) = 0;
  /// "lcm" or "serial".
  virtual const char* name() const = 0;
  /// Backend counters (name, total) for the process status.
  virtual std::vector<std::pair<std::string, int64_t>> counters() const = 0;
};

/// Publishes ucon::wheel_cmd_t on `channel` (BASE_WHEEL_CMD).
class LcmMotorBackend : public MotorBackend {
 public:
  LcmMotorBackend(lcm::LCM& lcm, std::string channel) : lcm_(lcm), channel_(std::move(channel)) {}
  bool send(const ucon::wheel_cmd_t& cmd) override;
  const char* name() const override { return "lcm"; }
  std::vector<std::pair<std::string, int64_t>> counters() const override;

 private:
  lcm::LCM& lcm_;
  std::string channel_;
  int64_t sent_ = 0;
  int64_t errors_ = 0;
};

/// Writes wheel frames to a serial port, in the motor board's channel order and signs.
class SerialMotorBackend : public MotorBackend {
 public:
  SerialMotorBackend(std::unique_ptr<SerialPort> port, const mecanum::MecanumParams& mecanum)
      : port_(std::move(port)), kin_(mecanum) {}
  bool send(const ucon::wheel_cmd_t& cmd) override;
  const char* name() const override { return "serial"; }
  std::vector<std::pair<std::string, int64_t>> counters() const override;

 private:
  std::unique_ptr<SerialPort> port_;
  mecanum::MecanumKinematics kin_;
  uint16_t seq_ = 0;
  int64_t sent_ = 0;
  int64_t clamped_ = 0;
};

}  // namespace base_controller
}  // namespace ucon
