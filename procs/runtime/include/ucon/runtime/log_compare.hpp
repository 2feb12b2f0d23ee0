#pragma once
/// @file log_compare.hpp
/// Compares two LCM logs message by message (channel, then every decoded field) and names the
/// first difference: "event 12 on PERCEPTION_OBJECTS (ucon.tracked_objects_t): field
/// objects[2].vx: 0.31 vs 0.32". Receive timestamps are ignored: replay is judged on content.

#include <string>

namespace ucon {
namespace runtime {

struct LogComparison {
  bool identical = false;
  bool error = false;          ///< a log could not be read (see message)
  std::string message;         ///< first difference or error; empty when identical
  long events_compared = 0;
};

/// Compares the events of `a` and `b` whose channel matches `channel_regex` (all if empty).
LogComparison compareLogs(const std::string& a, const std::string& b,
                          const std::string& channel_regex = "");

}  // namespace runtime
}  // namespace ucon
