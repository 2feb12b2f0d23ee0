#pragma once
/// @file point_packet.hpp
/// Layout of the Mid-360 point-data and IMU packets (Livox SDK2; docs/reference.md) and the
/// encoders the simulator uses to emit them. All multi-byte fields are little-endian.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ucon {
namespace livox {

constexpr std::size_t kPointHeaderSize = 36;  ///< bytes before the first record
constexpr std::size_t kCrcOffset = 24;        ///< offset of the header's crc32 field
constexpr std::size_t kCrcStart = 28;         ///< crc32 covers [28, length): timestamp + records
constexpr std::size_t kPointsPerPacket = 96;  ///< records per point packet sent by a Mid-360
constexpr std::size_t kMaxPacketSize = 65535;  ///< the length field is 16 bits
constexpr double kStandardGravity = 9.80665;  ///< [m/s^2] per g (IMU acceleration is sent in g)

/// data_type byte of a packet.
enum class DataType : uint8_t {
  kImu = 0,            ///< float gyro xyz [rad/s], float acc xyz [g]; 24 B, one record
  kCartesianHigh = 1,  ///< int32 xyz [mm], reflectivity, tag; 14 B
  kCartesianLow = 2,   ///< int16 xyz [cm], reflectivity, tag; 8 B
  kSpherical = 3,      ///< uint32 depth [mm], uint16 theta, phi [0.01 deg], reflectivity, tag; 10 B
};

/// time_type byte: how the sensor's timestamps were obtained.
enum class TimeType : uint8_t {
  kNone = 0,  ///< ns since power-on, not synchronised
  kPtp = 1,   ///< IEEE 1588 / gPTP
  kGps = 2,   ///< GPS PPS
};

/// True for data types 0..3.
bool isKnownDataType(uint8_t data_type);
/// Bytes per record of `data_type`; 0 for an unknown type.
std::size_t recordSize(uint8_t data_type);
/// "imu", "cartesian_high", "cartesian_low", "spherical" or "unknown".
const char* toString(DataType type);

/// All fields of the 36-byte header, in wire order.
struct PacketHeader {
  uint8_t version = 0;         ///< protocol version, 0
  uint16_t length = 0;         ///< length of the whole packet [bytes]
  uint16_t time_interval = 0;  ///< [0.1 us]; point i is at timestamp + i*time_interval*100/dot_num ns
  uint16_t dot_num = 0;        ///< records in this packet
  uint16_t udp_cnt = 0;        ///< +1 per packet, restarts each frame
  uint8_t frame_cnt = 0;       ///< sensor frame counter (wraps at 256)
  uint8_t data_type = 0;       ///< DataType
  uint8_t time_type = 0;       ///< TimeType
  std::array<uint8_t, 12> reserved{};
  uint32_t crc32 = 0;          ///< CRC-32 over bytes [28, length)
  uint64_t timestamp_ns = 0;   ///< time of the first point [ns]
};

/// Writes `h` into the first 36 bytes of `out` (which must hold at least 36 bytes).
void writeHeader(const PacketHeader& h, uint8_t* out);
/// Reads the 36-byte header at `in` (which must hold at least 36 bytes).
PacketHeader readHeader(const uint8_t* in);

/// One point as the simulator produces it, in the sensor frame.
struct LidarPoint {
  float x = 0;               ///< [m]
  float y = 0;               ///< [m]
  float z = 0;               ///< [m]
  uint8_t reflectivity = 0;  ///< 0..255
  uint8_t tag = 0;           ///< Mid-360 tag (see MidTag); 0 = a normal point
};

/// The Mid-360's tag byte: three 2-bit fields, each the sensor's confidence that the return is
/// not a real surface point. 0 is a normal point; 1-3 flag it (a higher value, more confident
/// for a Mid-360). Bits 6-7 are reserved. (Older Livox sensors used these bits for other
/// things: return number, intensity-based noise.)
struct MidTag {
  /// Bits 0-1: "sticking" (adhesion) between nearby objects: a point between two surfaces.
  static uint8_t sticking(uint8_t tag) { return tag & 0x3u; }
  /// Bits 2-3: rain, fog, dust (or other particles in the air).
  static uint8_t rainFogDust(uint8_t tag) { return (tag >> 2) & 0x3u; }
  /// Bits 4-5: other noise.
  static uint8_t otherNoise(uint8_t tag) { return (tag >> 4) & 0x3u; }
  static uint8_t make(uint8_t sticking, uint8_t rain_fog_dust, uint8_t other_noise) {
    return static_cast<uint8_t>((sticking & 3u) | ((rain_fog_dust & 3u) << 2) |
                                ((other_noise & 3u) << 4));
  }
};

/// One IMU sample in SI units, sensor frame (the wire format carries acceleration in g).
struct ImuSample {
  float gyro_x = 0;  ///< [rad/s]
  float gyro_y = 0;
  float gyro_z = 0;
  float acc_x = 0;   ///< [m/s^2]
  float acc_y = 0;
  float acc_z = 0;
};

/// Header fields the sender chooses; the encoder fills length, dot_num, data_type and crc32.
struct PacketInfo {
  uint64_t timestamp_ns = 0;   ///< time of the first point [ns]
  uint16_t time_interval = 0;  ///< [0.1 us] = dot_num * point spacing (see PacketHeader)
  uint16_t udp_cnt = 0;        ///< +1 per packet, restarts each frame
  uint8_t frame_cnt = 0;       ///< sensor frame counter
  TimeType time_type = TimeType::kNone;
  uint8_t version = 0;         ///< 0; other values only to build bad packets in tests
};

/// Outcome of an encoder.
enum class EncodeStatus {
  kOk,
  kUnknownDataType,  ///< not 1, 2 or 3 for a point packet
  kTooManyPoints,    ///< the packet would exceed 65535 bytes
  kNonFinite,        ///< a NaN or Inf coordinate / IMU value
  kOutOfRange,       ///< a coordinate does not fit the record's integer field
};
const char* toString(EncodeStatus status);

/// Encodes `n` points as one point packet of `type` (1, 2 or 3) into `out` (resized; its
/// capacity is reused). Coordinates are rounded to the record's resolution (1 mm, 1 cm, or
/// 1 mm / 0.01 deg). On error `out` is left empty.
EncodeStatus encodePointPacket(const PacketInfo& info, DataType type, const LidarPoint* points,
                               std::size_t n, std::vector<uint8_t>& out);
inline EncodeStatus encodePointPacket(const PacketInfo& info, DataType type,
                                      const std::vector<LidarPoint>& points,
                                      std::vector<uint8_t>& out) {
  return encodePointPacket(info, type, points.data(), points.size(), out);
}

/// Encodes one IMU packet (data type 0, dot_num 1); acceleration is converted from m/s^2 to g.
EncodeStatus encodeImuPacket(const PacketInfo& info, const ImuSample& sample,
                             std::vector<uint8_t>& out);

}  // namespace livox
}  // namespace ucon
