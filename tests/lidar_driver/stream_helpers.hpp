#pragma once
// Test helper: a synthetic Mid-360 packet stream (96-point type-1 packets at a fixed point
// rate), built with the protocol library's encoder.
#include <cstdint>
#include <vector>

#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/livox/protocol.hpp"

namespace driver_test {

/// Packets of `n` points each, the first point at `t0_ns`, points `dt_ns` apart; frame_cnt
/// changes every `per_frame` packets (udp_cnt restarts). Point j of the whole stream is at
/// (1 + (j % 10), 0.5, -0.25) metres with reflectivity j % 256.
inline std::vector<std::vector<uint8_t>> makeStream(int packets, uint64_t t0_ns, uint64_t dt_ns,
                                                    int n = 96, int per_frame = 1000,
                                                    ucon::livox::TimeType time_type = ucon::livox::TimeType::kPtp) {
  std::vector<std::vector<uint8_t>> out;
  std::vector<ucon::livox::LidarPoint> pts(static_cast<std::size_t>(n));
  for (int k = 0; k < packets; ++k) {
    for (int i = 0; i < n; ++i) {
      const int j = k * n + i;
      pts[static_cast<std::size_t>(i)] =
          ucon::livox::LidarPoint{1.0f + static_cast<float>(j % 10), 0.5f, -0.25f,
                                  static_cast<uint8_t>(j % 256), 0};
    }
    ucon::livox::PacketInfo info;
    info.timestamp_ns = t0_ns + static_cast<uint64_t>(k) * static_cast<uint64_t>(n) * dt_ns;
    info.time_interval = static_cast<uint16_t>(static_cast<uint64_t>(n) * dt_ns / 100);
    info.udp_cnt = static_cast<uint16_t>(k % per_frame);
    info.frame_cnt = static_cast<uint8_t>(k / per_frame);
    info.time_type = time_type;
    std::vector<uint8_t> b;
    ucon::livox::encodePointPacket(info, ucon::livox::DataType::kCartesianHigh, pts.data(), pts.size(), b);
    out.push_back(std::move(b));
  }
  return out;
}

/// Parameters for node tests: sensor frame (no extrinsic), no filters, 50 Hz.
inline ucon::lidar_driver::DriverParams plainParams() {
  ucon::lidar_driver::DriverParams p;
  p.frame.apply_extrinsic = false;
  p.filter.min_range_m = 0.0;
  p.filter.max_range_m = 1000.0;
  p.frame.rate_hz = 50;
  return p;
}

}  // namespace driver_test
