#pragma once
/// @file control_responder.hpp
/// The emulated sensor's side of the Livox SDK2 control protocol: answers discovery and
/// set-key-value requests with correctly framed acks (ucon::livox encoders) and keeps the state
/// they change (where point/IMU packets go, work mode, point data type, IMU enable). Pure: the
/// main receives the datagrams and sends the replies.

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
  uint8_t work_mode = 0x01;   ///< livox::WorkMode; points are sent only in kNormal
  uint8_t data_type = 1;      ///< point record type 1, 2 or 3
  bool imu_enabled = true;
  bool sampling() const { return work_mode == static_cast<uint8_t>(livox::WorkMode::kNormal); }
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

  /// Handles one received datagram; returns the ack to send back to its sender, or nullopt
  /// (malformed frames and acks are not answered).
  std::optional<std::vector<uint8_t>> handle(const uint8_t* data, std::size_t size);

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
