#pragma once
/// @file sensor_configurator.hpp
/// The control path as a state machine without sockets: it says which control frames to send
/// and when, and consumes the answers. The process moves the bytes and supplies a monotonic
/// time; tests drive it directly.
///
/// Sequence: [discovery request, repeated until a discovery ack] -> set key-values
/// (point-data host IP/port, IMU host IP/port, IMU enable, work mode), repeated until the ack
/// -> done. Any step unanswered until `timeout_s` after start -> failed, with a message that
/// names what to check.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/livox/control.hpp"

namespace ucon {
namespace lidar_driver {

/// A datagram to send.
struct OutgoingDatagram {
  std::array<uint8_t, 4> ip{};
  uint16_t port = 0;
  std::vector<uint8_t> bytes;
};

class SensorConfigurator {
 public:
  enum class State { kDiscovering, kConfiguring, kDone, kFailed };

  /// `params` must have valid IPv4 strings (DriverParams::read checks them).
  explicit SensorConfigurator(const DriverParams& params);

  /// Requests due at monotonic time `t_s` [s] (the first call starts the clock). Also moves
  /// to kFailed when the timeout has passed.
  std::vector<OutgoingDatagram> poll(double t_s);

  /// One datagram received on the host command port. Frames that are not the awaited ack are
  /// counted and ignored.
  void onDatagram(const uint8_t* data, std::size_t size, double t_s);

  State state() const { return state_; }
  /// Why it failed (empty unless kFailed): what was asked, of whom, and what to check.
  const std::string& failure() const { return failure_; }
  /// The sensor's address and command port (configured or discovered).
  const std::array<uint8_t, 4>& sensorIp() const { return sensor_ip_; }
  uint16_t sensorCommandPort() const { return sensor_cmd_port_; }
  /// Serial number from the discovery ack (empty without discovery).
  const std::string& serial() const { return serial_; }
  int requestsSent() const { return requests_sent_; }
  int ignoredDatagrams() const { return ignored_; }

 private:
  void fail(const std::string& what);
  livox::ControlFrame currentRequest() const;

  DriverParams params_;
  State state_;
  std::array<uint8_t, 4> sensor_ip_{};
  uint16_t sensor_cmd_port_ = 0;
  std::string serial_;
  uint32_t seq_ = 1;
  livox::ControlFrame pending_;
  double start_s_ = -1;
  double next_send_s_ = 0;
  int requests_sent_ = 0;
  int ignored_ = 0;
  std::string failure_;
};

/// "discovering" | "configuring" | "done" | "failed".
const char* toString(SensorConfigurator::State s);

}  // namespace lidar_driver
}  // namespace ucon
