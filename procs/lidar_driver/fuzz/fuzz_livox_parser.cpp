// libFuzzer target: the point/IMU packet parser and the control-frame decoder must never
// crash, read out of bounds, or return non-finite values, whatever the bytes. Run (bounded):
//   build/bin/fuzz-livox-parser -max_total_time=60 -max_len=2048
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <algorithm>

#include <vector>

#include "ucon/lidar_driver/captured_udp.hpp"
#include "ucon/livox/control.hpp"
#include "ucon/livox/crc.hpp"
#include "ucon/livox/packet_parser.hpp"

namespace {
void checkPacket(const uint8_t* data, size_t size) {
  using namespace ucon::livox;
  static ParsedPacket pkt;
  const ParseStatus st = parsePacket(data, size, pkt);
  if (st == ParseStatus::kOk) {
    if (pkt.header.length != size) std::abort();
    if (pkt.type == DataType::kImu) {
      if (!std::isfinite(pkt.imu.acc_x) || !std::isfinite(pkt.imu.acc_y) ||
          !std::isfinite(pkt.imu.acc_z) || !std::isfinite(pkt.imu.gyro_x)) {
        std::abort();
      }
    } else {
      if (pkt.points.size() + pkt.bad_points != pkt.header.dot_num) std::abort();
      for (const ParsedPoint& p : pkt.points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
        if (p.time_ns < pkt.header.timestamp_ns) std::abort();
      }
    }
  } else if (!pkt.points.empty()) {
    std::abort();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ucon::livox;
  checkPacket(data, size);
  // Random bytes almost never carry a valid crc32; parse a copy with the crc (and the length
  // field) made consistent too, so the fuzzer reaches the record decoding.
  if (size >= kPointHeaderSize && size <= 0xFFFF) {
    static std::vector<uint8_t> fixed;
    fixed.assign(data, data + size);
    fixed[1] = static_cast<uint8_t>(size & 0xFF);
    fixed[2] = static_cast<uint8_t>(size >> 8);
    const uint32_t c = crc32(fixed.data() + kCrcStart, size - kCrcStart);
    for (int i = 0; i < 4; ++i) fixed[kCrcOffset + i] = static_cast<uint8_t>(c >> (8 * i));
    checkPacket(fixed.data(), size);
  }
  // Any byte string is a captured frame of some link type: the datagram found lies inside it.
  for (int link : {0, 1, 101, 113, 276}) {
    if (const auto udp = ucon::lidar_driver::extractUdp(link, data, size, nullptr)) {
      if (udp->payload < data || udp->payload + udp->size > data + size) std::abort();
    }
  }
  // Any byte string, with the crc fixed up or not, must be handled by the control decoder.
  ControlFrame f;
  if (decodeControlFrame(data, size, f) == ControlStatus::kOk) {
    // A decoded frame re-encodes to the same bytes (the reserved bytes are not kept, so only
    // when they were zero).
    bool reserved_zero = true;
    for (size_t i = 12; i < 18; ++i) reserved_zero = reserved_zero && data[i] == 0;
    if (reserved_zero) {
      const auto again = encodeControlFrame(f);
      if (again.size() != size || !std::equal(again.begin(), again.end(), data)) std::abort();
    }
    (void)decodeKeyValueList(f.data);
    (void)parseDiscoveryAck(f);
    (void)parseSetKeyValueAck(f);
    (void)parseQueryRequest(f);
    (void)parseQueryAck(f);
    (void)parsePushMessage(f);
  }
  return 0;
}
