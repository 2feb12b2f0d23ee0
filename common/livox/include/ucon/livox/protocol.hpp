#pragma once
/// @file protocol.hpp
/// The Livox Mid-360 protocol (Livox SDK2; REFERENCE.md §2) in one include: CRCs, point/IMU
/// packet layout and encoders, the packet parser, control frames, and the default ports.
/// Pure functions over bytes; the driver and the simulator own the sockets.

#include <cstdint>

#include "ucon/livox/control.hpp"
#include "ucon/livox/crc.hpp"
#include "ucon/livox/packet_parser.hpp"
#include "ucon/livox/point_packet.hpp"

namespace ucon {
namespace livox {

/// Host-side default UDP ports (what the driver binds).
constexpr uint16_t kHostCommandPort = 56101;
constexpr uint16_t kHostPushPort = 56201;
constexpr uint16_t kHostPointPort = 56301;
constexpr uint16_t kHostImuPort = 56401;
constexpr uint16_t kHostLogPort = 56501;
/// Sensor-side default UDP ports.
constexpr uint16_t kSensorDiscoveryPort = 56000;  ///< discovery requests (broadcast) go here
constexpr uint16_t kSensorCommandPort = 56100;
constexpr uint16_t kSensorPushPort = 56200;
constexpr uint16_t kSensorPointPort = 56300;
constexpr uint16_t kSensorImuPort = 56400;
constexpr uint16_t kSensorLogPort = 56500;

}  // namespace livox
}  // namespace ucon
