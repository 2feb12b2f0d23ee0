#pragma once
/// @file message_time.hpp
/// The time policy shared by ucon-mcap and ucon-foxglove-bridge: a message's time is its own
/// utime (sensor or simulation time), never the time it was received. A message without one
/// -- utime <= 0 ("invalid" in every ucon type), or a type whose utime is the wall clock
/// (LOG_METADATA, PROC_STATUS) -- takes the time of the latest message that had one, so that
/// it lands where it happened in the run instead of decades away on the wall-clock axis.

#include <cstddef>
#include <cstdint>
#include <optional>

namespace ucon {
namespace foxglove {

struct LcmTypeInfo;

class MessageClock {
 public:
  /// The message's own time [us]: its utime when its type has message time and utime > 0;
  /// nullopt otherwise.
  static std::optional<int64_t> ownTime(const LcmTypeInfo& type, const void* data, std::size_t size);

  /// Time [us] for this message: its own time (which becomes the clock), or the clock.
  /// nullopt for an untimed message before any timed one (the caller decides).
  std::optional<int64_t> timeOf(const LcmTypeInfo& type, const void* data, std::size_t size);

  /// The latest own time seen [us]; 0 before the first.
  int64_t now() const { return now_; }
  bool started() const { return started_; }

 private:
  int64_t now_ = 0;
  bool started_ = false;
};

}  // namespace foxglove
}  // namespace ucon
