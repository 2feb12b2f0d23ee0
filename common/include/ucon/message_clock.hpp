#pragma once
/// @file message_clock.hpp
/// "Now" for a node, driven by the utime of the messages it is given, never by the wall clock.

#include <cstdint>

namespace ucon {

/// Monotonic clock advanced by message times.
///
/// observe() moves "now" forward to a message's utime; a utime older than "now" does not move
/// it back (it is counted, so a node can report out-of-order input). Replaying the same
/// messages gives the same sequence of "now" values.
class MessageClock {
 public:
  /// Outcome of observing one message time.
  enum class Observation { kAdvanced, kSame, kOlder, kInvalid };

  /// Feeds a message time [us]. Non-positive times are invalid and ignored.
  Observation observe(int64_t utime) {
    if (utime <= 0) {
      ++invalid_;
      return Observation::kInvalid;
    }
    if (now_ == 0 || utime > now_) {
      now_ = utime;
      return Observation::kAdvanced;
    }
    if (utime == now_) return Observation::kSame;
    ++older_;
    return Observation::kOlder;
  }

  /// Latest message time seen [us]; 0 before the first valid message.
  int64_t now() const { return now_; }
  /// True once a valid time has been observed.
  bool started() const { return now_ > 0; }
  /// now() - utime [s]; +inf-like large value if `utime` is 0 (never).
  double ageSeconds(int64_t utime) const {
    if (utime <= 0) return 1e18;
    return static_cast<double>(now_ - utime) * 1e-6;
  }
  /// Messages seen older than "now" (out of order).
  int64_t olderCount() const { return older_; }
  /// Messages with a non-positive utime.
  int64_t invalidCount() const { return invalid_; }

 private:
  int64_t now_ = 0;
  int64_t older_ = 0;
  int64_t invalid_ = 0;
};

}  // namespace ucon
