#pragma once
/// @file health_view.hpp
/// What `deploy/ucon status` shows of the processes' own status channels (<NAME>_STATUS,
/// ODOMETRY_HEALTH: ucon::process_status_t): per process the health and message of its latest
/// message, and its fault counters that are not zero. ucon-health collects the messages; this
/// keeps the latest per process and formats them. No I/O.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ucon/process_status_t.hpp"

namespace ucon {
namespace tools {

/// True for a counter that counts something going wrong: one of its words (separated by '_')
/// is bad, collisions, crc, drop(s|ped), error(s), expired, fail(ed|ures), gaps, ignored,
/// invalid, late, lost, malformed, mismatches, missed, nan, older, overflow(s), overrun(s),
/// refused, rejected, reinitialisations, resets, skipped, stale, timeout(s), truncated,
/// undecodable, unknown or wrong, or it contains out_of_order, non_finite or no_pose. E.g.
/// "frames_stale_pose", "decode_errors", "stops_trajectory_stale", "result_stop_no_pose",
/// "imu_gaps"; not "frames_in", "ticks", "goals_repeated" or "plan_restarts_from_pose" (a
/// process's own restarts are the launcher's RESTARTS column).
bool isFaultCounter(const std::string& name);

/// One process as its latest status message describes it.
struct HealthEntry {
  std::string name;     ///< process_status_t.name (the channel when empty)
  std::string channel;  ///< where it came from
  int8_t health = process_status_t::HEALTH_OK;
  std::string message;
  std::vector<std::pair<std::string, int64_t>> faults;  ///< fault counters > 0, message order
  int64_t messages = 0;  ///< status messages heard from it
};

/// "OK", "WARN", "ERROR" or "health <n>".
std::string healthName(int8_t health);

/// The latest status of each process heard.
class HealthView {
 public:
  /// Takes one status message heard on `channel`.
  void add(const std::string& channel, const process_status_t& msg);

  /// The entries: first those named in `expected` (in that order; a process never heard has
  /// messages == 0 and health -1), then the others heard, by name.
  std::vector<HealthEntry> entries(const std::vector<std::string>& expected) const;

  /// Text for people: one line per process (name, health, message, or "no status heard"),
  /// and below it, indented, its fault counters that are not zero.
  std::string format(const std::vector<std::string>& expected, double listened_s) const;

 private:
  std::vector<HealthEntry> heard_;  // in order of first message
};

}  // namespace tools
}  // namespace ucon
