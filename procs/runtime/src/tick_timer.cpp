#include "ucon/runtime/tick_timer.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace runtime {

TickTimer::TickTimer(Mode mode, double rate_hz)
    : mode_(mode),
      period_us_(std::max<int64_t>(1, static_cast<int64_t>(std::llround(1e6 / std::max(rate_hz, 1e-3))))) {}

void TickTimer::observe(int64_t msg_utime, int64_t wall_utime) {
  if (msg_utime <= 0 || msg_utime < anchor_msg_) return;
  anchor_msg_ = msg_utime;
  anchor_wall_ = wall_utime;
  if (next_wall_ == 0) next_wall_ = wall_utime;
  if (next_tick_ == 0) {
    // First tick on the period grid at or after the first message.
    next_tick_ = ((msg_utime + period_us_ - 1) / period_us_) * period_us_;
  }
}

std::vector<int64_t> TickTimer::due(int64_t wall_utime) {
  std::vector<int64_t> out;
  if (anchor_msg_ == 0) return out;
  if (mode_ == Mode::kLive) {
    if (wall_utime < next_wall_) return out;
    int64_t t = anchor_msg_ + std::max<int64_t>(0, wall_utime - anchor_wall_);
    t = std::max(t, last_tick_ + 1);
    out.push_back(t);
    last_tick_ = t;
    next_wall_ += period_us_;
    if (next_wall_ <= wall_utime) next_wall_ = wall_utime + period_us_;  // fell behind: no burst
    return out;
  }
  const int64_t pending = next_tick_ < anchor_msg_ ? (anchor_msg_ - 1 - next_tick_) / period_us_ + 1 : 0;
  if (pending > kMaxBurst) {
    skipped_ += pending - kMaxBurst;
    next_tick_ += (pending - kMaxBurst) * period_us_;
  }
  while (next_tick_ < anchor_msg_) {
    out.push_back(next_tick_);
    last_tick_ = next_tick_;
    next_tick_ += period_us_;
  }
  return out;
}

}  // namespace runtime
}  // namespace ucon
