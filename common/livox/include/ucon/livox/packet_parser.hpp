#pragma once
/// @file packet_parser.hpp
/// The point/IMU packet parser: a pure function over the bytes of one UDP datagram.
/// Every malformed input gives a status, never a crash or a non-finite value.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ucon/livox/point_packet.hpp"

namespace ucon {
namespace livox {

/// Outcome of parsing one datagram, in the order the checks are made.
enum class ParseStatus {
  kOk,
  kTruncatedHeader,  ///< fewer than 36 bytes
  kBadVersion,       ///< version byte is not 0
  kBadLength,        ///< length field != datagram size, or != 36 + dot_num * record size
                     ///< (IMU: dot_num must be 1)
  kUnknownDataType,  ///< data_type not in 0..3
  kBadCrc,           ///< crc32 over [28, length) does not match
  kNonFinite,        ///< an IMU value is NaN or Inf
  kBadValue,         ///< timestamp >= 2^62 ns, or a spherical angle out of range
                     ///< (theta > 180 deg, phi >= 360 deg)
};
/// Short snake_case name, e.g. "bad_crc"; usable as a status counter name.
const char* toString(ParseStatus status);

/// One decoded point, sensor frame.
struct ParsedPoint {
  float x = 0;               ///< [m]
  float y = 0;               ///< [m]
  float z = 0;               ///< [m]
  uint8_t reflectivity = 0;  ///< 0..255
  uint8_t tag = 0;           ///< Livox tag bits
  uint64_t time_ns = 0;      ///< sensor time of this point [ns]
};

/// A decoded packet. `points` is filled for data types 1-3, `imu` for data type 0.
struct ParsedPacket {
  PacketHeader header;
  DataType type = DataType::kCartesianHigh;
  std::vector<ParsedPoint> points;  ///< capacity is reused between calls
  ImuSample imu;                    ///< SI units (acceleration converted from g)
};

/// Parses one datagram of `size` bytes. On kOk `out` holds the packet; on any other status
/// `out.points` is empty and the rest of `out` is unspecified.
ParseStatus parsePacket(const uint8_t* data, std::size_t size, ParsedPacket& out);

}  // namespace livox
}  // namespace ucon
