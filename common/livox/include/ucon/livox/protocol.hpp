#pragma once
/// @file protocol.hpp
/// The Livox Mid-360 protocol (Livox SDK2; docs/reference.md) in one include: CRCs, point/IMU
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
/// Discovery: the host broadcasts the request to this port (from its own port 56000) and the
/// sensor answers by broadcast to port 56000: the host must receive on a socket bound to
/// 0.0.0.0:56000 (Linux never delivers a broadcast to a socket bound to a unicast address).
constexpr uint16_t kSensorDiscoveryPort = 56000;
constexpr uint16_t kSensorCommandPort = 56100;
constexpr uint16_t kSensorPushPort = 56200;
constexpr uint16_t kSensorPointPort = 56300;
constexpr uint16_t kSensorImuPort = 56400;
constexpr uint16_t kSensorLogPort = 56500;

}  // namespace livox
}  // namespace ucon
