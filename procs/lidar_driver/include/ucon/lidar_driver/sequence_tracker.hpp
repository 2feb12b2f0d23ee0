#pragma once
/// @file sequence_tracker.hpp
/// Lost-packet accounting from the udp_cnt / frame_cnt fields of one packet stream.

#include <cstdint>

namespace ucon {
namespace lidar_driver {

/// Counts packets missing from a stream. udp_cnt increments per packet; the Mid-360 restarts
/// it when frame_cnt changes. Both that and a counter that keeps running across frame_cnt
/// changes are accepted: on a frame_cnt change, udp_cnt == 0 or == previous + 1 means nothing
/// was lost. Packets lost at the very end of a sensor frame cannot be seen (the next frame
/// restarts the count); they show up as a short frame instead.
class SequenceTracker {
 public:
  struct Result {
    int64_t lost = 0;           ///< packets missing just before this one (>= 0)
    bool out_of_order = false;  ///< this packet's udp_cnt is at or behind the last one seen
  };

  Result observe(uint8_t frame_cnt, uint16_t udp_cnt) {
    Result r;
    if (started_) {
      const uint16_t expected = static_cast<uint16_t>(last_udp_ + 1);
      if (frame_cnt == last_frame_) {
        const uint16_t d = static_cast<uint16_t>(udp_cnt - expected);
        if (d < 0x8000u) {
          r.lost = d;
        } else {
          r.out_of_order = true;  // duplicate or reordered: do not move the reference back
          return r;
        }
      } else if (udp_cnt != 0 && udp_cnt != expected) {
        const uint16_t d = static_cast<uint16_t>(udp_cnt - expected);
        // A running counter that skipped d packets, else a restarted one that lost its first
        // udp_cnt packets.
        r.lost = (d < 0x8000u && udp_cnt > last_udp_) ? d : udp_cnt;
      }
    }
    started_ = true;
    last_frame_ = frame_cnt;
    last_udp_ = udp_cnt;
    return r;
  }

  /// Forgets the stream (sensor rebooted, counters restarted).
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  uint8_t last_frame_ = 0;
  uint16_t last_udp_ = 0;
};

}  // namespace lidar_driver
}  // namespace ucon
