#pragma once
/// @file control_responder.hpp
/// The emulated sensor's side of the Livox SDK2 control protocol, as a Mid-360 behaves:
/// answers discovery (by broadcast: the main sends that answer to the broadcast address),
/// set-key-value and query requests with correctly framed acks (ucon::livox encoders), rejects
/// what a Mid-360 rejects (a work mode other than 0x01 sampling / 0x02 idle, an unknown key),
/// and keeps the state the commands change (where point/IMU/status packets go, work mode,
/// point data type, scan pattern, IMU enable). Pure: the main receives the datagrams and
/// sends the replies.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ucon/livox/control.hpp"

namespace ucon {
namespace simulator {

/// State the driver can change through control commands.
struct SensorState {
  std::array<uint8_t, 4> point_host_ip{{127, 0, 0, 1}};
  uint16_t point_host_port = 56301;
  std::array<uint8_t, 4> imu_host_ip{{127, 0, 0, 1}};
  uint16_t imu_host_port = 56401;
  std::array<uint8_t, 4> push_host_ip{{0, 0, 0, 0}};  ///< state-info host (key 0x0005); unset
  uint16_t push_host_port = 0;
  uint8_t work_mode = 0x01;   ///< livox::WorkMode; points are sent only in kSampling
  uint8_t data_type = 1;      ///< point record type 1, 2 or 3
  uint8_t pattern_mode = 0;   ///< 0 non-repetitive (the emulated pattern is always that)
  bool imu_enabled = true;
  bool sampling() const { return work_mode == static_cast<uint8_t>(livox::WorkMode::kSampling); }
};

/// Counters of handled datagrams.
struct ControlCounters {
  int64_t requests = 0;       ///< well-formed requests answered
  int64_t malformed = 0;      ///< datagrams that are not valid control frames
  int64_t unsupported = 0;    ///< valid frames with a command this emulator does not implement
  int64_t rejected_keys = 0;  ///< keys answered with an error return code
};

class ControlResponder {
 public:
  ControlResponder(SensorState initial, std::array<uint8_t, 4> sensor_ip, uint16_t command_port,
                   std::string serial);

  /// Handles one received datagram; returns the ack to send back, or nullopt (malformed frames
  /// and acks are not answered). `broadcast` (if given) is set when the ack is a discovery
  /// answer, which a Mid-360 sends by broadcast, not to the requester's address.
  std::optional<std::vector<uint8_t>> handle(const uint8_t* data, std::size_t size,
                                             bool* broadcast = nullptr);
  const std::string& serial() const { return serial_; }
  const std::array<uint8_t, 4>& sensorIp() const { return sensor_ip_; }

  const SensorState& state() const { return state_; }
  const ControlCounters& counters() const { return counters_; }
  /// Incremented whenever a set command changed the state (the main re-reads it).
  uint64_t generation() const { return generation_; }

 private:
  livox::ControlFrame handleSet(const livox::ControlFrame& req);

  SensorState state_;
  std::array<uint8_t, 4> sensor_ip_;
  uint16_t command_port_;
  std::string serial_;
  ControlCounters counters_;
  uint64_t generation_ = 0;
};

}  // namespace simulator
}  // namespace ucon
