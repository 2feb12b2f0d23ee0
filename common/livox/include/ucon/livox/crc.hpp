#pragma once
/// @file crc.hpp
/// The two checksums of the Livox SDK2 protocol.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ucon {
namespace livox {

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor);
/// "123456789" -> 0x29B1. Used over bytes 0-17 of a control frame.
uint16_t crc16CcittFalse(const uint8_t* data, std::size_t size);
inline uint16_t crc16CcittFalse(const std::vector<uint8_t>& bytes) {
  return crc16CcittFalse(bytes.data(), bytes.size());
}

/// Standard CRC-32 (IEEE 802.3, reflected, init and final xor 0xFFFFFFFF);
/// "123456789" -> 0xCBF43926. Used over point-packet payloads and control-frame data.
uint32_t crc32(const uint8_t* data, std::size_t size);
inline uint32_t crc32(const std::vector<uint8_t>& bytes) { return crc32(bytes.data(), bytes.size()); }

}  // namespace livox
}  // namespace ucon
