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
  kBadCrc,           ///< never returned by parsePacket (which reports the crc32 in
                     ///< ParsedPacket::crc); a receiver that drops the packet for it says so
  kNonFinite,        ///< an IMU value is NaN or Inf
  kBadValue,         ///< timestamp >= 2^62 ns (sensor times would overflow)
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

/// What the header's crc32 field says about the packet. Livox's own SDK and ROS driver never
/// check this field, so a sensor (or firmware) that leaves it 0 must not lose its data; the
/// parser only reports it and the receiver decides (see LidarDriverNode).
enum class CrcCheck : uint8_t {
  kAbsent,    ///< the field is 0: not filled in
  kMatch,     ///< CRC-32 over [28, length) equals the field
  kMismatch,  ///< non-zero and different
};
const char* toString(CrcCheck c);

/// A decoded packet. `points` is filled for data types 1-3, `imu` for data type 0.
struct ParsedPacket {
  PacketHeader header;
  DataType type = DataType::kCartesianHigh;
  CrcCheck crc = CrcCheck::kAbsent;
  std::vector<ParsedPoint> points;  ///< capacity is reused between calls
  /// Records that are not a measurement and were left out of `points`: spherical records with
  /// an angle out of range (theta > 180 deg or phi > 360 deg). Only such a record is lost; the
  /// rest of the packet is kept. points.size() + bad_points == dot_num.
  std::size_t bad_points = 0;
  ImuSample imu;                    ///< SI units (acceleration converted from g)
};

/// Parses one datagram of `size` bytes. On kOk `out` holds the packet; on any other status
/// `out.points` is empty and the rest of `out` is unspecified. A bad crc32 is not a failure
/// here: it is reported in `out.crc`.
ParseStatus parsePacket(const uint8_t* data, std::size_t size, ParsedPacket& out);

}  // namespace livox
}  // namespace ucon
