#pragma once
/// @file serial_frame.hpp
/// The wheel-speed frame sent to the motor board over a serial line (pure encode/decode; the
/// tty itself is in serial_port.hpp). Layout, 16 bytes, multi-byte fields little-endian:
///
/// | off | size | field                                                        |
/// |-----|------|--------------------------------------------------------------|
/// | 0   | 2    | sync 0xAA 0x55                                               |
/// | 2   | 1    | version (1)                                                  |
/// | 3   | 1    | flags: bit 0 = enable (0 = motors off / brake), others 0     |
/// | 4   | 2    | sequence number, uint16, +1 per frame, wraps                 |
/// | 6   | 8    | 4 x int16 wheel speeds in motor-channel order, 0.01 rad/s/LSB |
/// | 14  | 2    | CRC-16/CCITT-FALSE over bytes 0..13                          |
///
/// Speeds beyond the int16 range (+-327.67 rad/s) are clamped when encoding.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ucon {
namespace base_controller {

inline constexpr std::size_t kWheelFrameSize = 16;
inline constexpr uint8_t kWheelFrameSync0 = 0xAA;
inline constexpr uint8_t kWheelFrameSync1 = 0x55;
inline constexpr uint8_t kWheelFrameVersion = 1;
inline constexpr double kWheelSpeedLsb = 0.01;  ///< [rad/s] per count

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor);
/// "123456789" -> 0x29B1.
uint16_t crc16CcittFalse(const uint8_t* data, std::size_t n);

/// One decoded frame.
struct WheelFrame {
  uint16_t seq = 0;
  bool enable = false;
  std::array<int16_t, 4> raw{};  ///< counts, motor-channel order

  /// Wheel speeds [rad/s] (raw * kWheelSpeedLsb).
  std::array<double, 4> speeds() const;
};

/// Encodes motor-channel speeds [rad/s]. A non-finite speed encodes the whole frame as
/// disabled with zero speeds. `clamped` (optional) receives how many values were clamped.
std::array<uint8_t, kWheelFrameSize> encodeWheelFrame(uint16_t seq, bool enable,
                                                      const std::array<double, 4>& speeds,
                                                      int* clamped = nullptr);

/// Outcome of decoding one frame.
enum class FrameStatus { kOk, kTooShort, kBadSync, kBadVersion, kBadCrc };
const char* toString(FrameStatus s);

/// Decodes the frame at data[0..n).
FrameStatus decodeWheelFrame(const uint8_t* data, std::size_t n, WheelFrame* out);

/// Byte-stream parser for the receiving side (a motor board, or a test): finds sync words,
/// checks CRCs, resynchronises after garbage. Deterministic; buffers at most one frame.
class WheelFrameParser {
 public:
  /// Feeds bytes; returns the frames completed by them.
  std::vector<WheelFrame> feed(const uint8_t* data, std::size_t n);
  int64_t crcErrors() const { return crc_errors_; }
  int64_t skippedBytes() const { return skipped_; }

 private:
  std::vector<uint8_t> buf_;
  int64_t crc_errors_ = 0;
  int64_t skipped_ = 0;
};

}  // namespace base_controller
}  // namespace ucon
