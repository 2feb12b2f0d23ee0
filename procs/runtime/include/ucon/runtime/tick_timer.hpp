#pragma once
/// @file tick_timer.hpp
/// When to run a periodic tick (TickRule::kPeriodic), and with which message time.
///
/// Live, the loop runs on its own timer (wall clock) so that a watchdog fires even when no
/// message arrives; the time passed to the node is message time: the newest message utime plus
/// the wall time elapsed since it was received. In replay ("message" mode) ticks fall on every
/// multiple of the period up to the newest message time, so a log replays identically.
/// The wall time is an argument: this class reads no clock.

#include <cstdint>
#include <vector>

namespace ucon {
namespace runtime {

class TickTimer {
 public:
  enum class Mode { kLive, kMessage };

  /// `rate_hz` > 0.
  TickTimer(Mode mode, double rate_hz);

  /// Notes a message with time `msg_utime` [us] received at wall time `wall_utime` [us].
  /// Non-positive or older message times are ignored.
  void observe(int64_t msg_utime, int64_t wall_utime);

  /// Tick times [us, message time] due at wall time `wall_utime`. Live: none or one. Message
  /// mode: every tick before the newest message time (at most kMaxBurst; a larger jump skips
  /// ahead and is counted); run them before handing that message to the node.
  std::vector<int64_t> due(int64_t wall_utime);

  /// Wall time [us] of the next live tick; 0 before the first message.
  int64_t nextWallDeadline() const { return next_wall_; }
  /// Ticks skipped after a jump in message time (message mode).
  int64_t skippedTicks() const { return skipped_; }

  static constexpr int kMaxBurst = 1000;

 private:
  Mode mode_;
  int64_t period_us_;
  int64_t anchor_msg_ = 0;   // newest message time
  int64_t anchor_wall_ = 0;  // wall time it was received
  int64_t next_wall_ = 0;
  int64_t next_tick_ = 0;    // message mode
  int64_t last_tick_ = 0;
  int64_t skipped_ = 0;
};

}  // namespace runtime
}  // namespace ucon
