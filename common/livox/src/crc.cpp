#include "ucon/livox/crc.hpp"

#include <zlib.h>

#include <array>
#include <limits>

namespace ucon {
namespace livox {

namespace {
// Byte-wise table for the MSB-first polynomial 0x1021.
std::array<uint16_t, 256> makeCrc16Table() {
  std::array<uint16_t, 256> t{};
  for (unsigned i = 0; i < 256; ++i) {
    uint16_t c = static_cast<uint16_t>(i << 8);
    for (int b = 0; b < 8; ++b) {
      c = (c & 0x8000u) ? static_cast<uint16_t>((c << 1) ^ 0x1021u) : static_cast<uint16_t>(c << 1);
    }
    t[i] = c;
  }
  return t;
}
}  // namespace

uint16_t crc16CcittFalse(const uint8_t* data, std::size_t size) {
  static const std::array<uint16_t, 256> kTable = makeCrc16Table();
  uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < size; ++i) {
    crc = static_cast<uint16_t>((crc << 8) ^ kTable[((crc >> 8) ^ data[i]) & 0xFFu]);
  }
  return crc;
}

uint32_t crc32(const uint8_t* data, std::size_t size) {
  uLong c = ::crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed very large buffers in chunks.
  constexpr std::size_t kChunk = std::numeric_limits<uInt>::max();
  while (size > 0) {
    const std::size_t n = size < kChunk ? size : kChunk;
    c = ::crc32(c, data, static_cast<uInt>(n));
    data += n;
    size -= n;
  }
  return static_cast<uint32_t>(c);
}

}  // namespace livox
}  // namespace ucon
