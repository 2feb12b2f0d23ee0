#pragma once
// Test helper: builds Livox point/IMU packets byte by byte, independently of the library's
// encoder, so parser tests do not just check the encoder against itself.
#include <cstdint>
#include <cstring>
#include <vector>

#include "ucon/livox/crc.hpp"

namespace livox_test {

struct Bytes {
  std::vector<uint8_t> b;
  void u8(uint8_t v) { b.push_back(v); }
  void u16(uint16_t v) { u8(v & 0xFF); u8(v >> 8); }
  void u32(uint32_t v) { u16(v & 0xFFFF); u16(v >> 16); }
  void u64(uint64_t v) { u32(static_cast<uint32_t>(v)); u32(static_cast<uint32_t>(v >> 32)); }
  void i16(int16_t v) { u16(static_cast<uint16_t>(v)); }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f32(float v) { uint32_t u; std::memcpy(&u, &v, 4); u32(u); }
};

/// Header with placeholder length and crc; records are appended afterwards, then finish().
inline Bytes header(uint8_t data_type, uint16_t dot_num, uint16_t time_interval, uint16_t udp_cnt,
                    uint8_t frame_cnt, uint64_t timestamp_ns, uint8_t time_type = 1) {
  Bytes h;
  h.u8(0);              // version
  h.u16(0);             // length, set by finish()
  h.u16(time_interval);
  h.u16(dot_num);
  h.u16(udp_cnt);
  h.u8(frame_cnt);
  h.u8(data_type);
  h.u8(time_type);
  for (int i = 0; i < 12; ++i) h.u8(0);
  h.u32(0);             // crc32, set by finish()
  h.u64(timestamp_ns);
  return h;
}

/// Writes the length field and the crc32 over [28, end).
inline std::vector<uint8_t> finish(Bytes p) {
  const uint16_t len = static_cast<uint16_t>(p.b.size());
  p.b[1] = len & 0xFF;
  p.b[2] = len >> 8;
  const uint32_t c = ucon::livox::crc32(p.b.data() + 28, p.b.size() - 28);
  for (int i = 0; i < 4; ++i) p.b[24 + i] = static_cast<uint8_t>(c >> (8 * i));
  return p.b;
}

/// Recomputes only the crc (after a test edited bytes past offset 28 on purpose, or to make
/// a header-only corruption pass the crc check).
inline void fixCrc(std::vector<uint8_t>& b) {
  const uint32_t c = ucon::livox::crc32(b.data() + 28, b.size() - 28);
  for (int i = 0; i < 4; ++i) b[24 + i] = static_cast<uint8_t>(c >> (8 * i));
}

}  // namespace livox_test
