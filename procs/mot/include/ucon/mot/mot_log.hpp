#pragma once
/// @file mot_log.hpp
/// CLEAR-MOT over an LCM log: SIM_GROUND_TRUTH vs PERCEPTION_OBJECTS (the I/O half of
/// ucon/mot/runtime_frames.hpp; reads the file with lcm::LogFile).

#include <cstdint>
#include <optional>
#include <string>

#include "ucon/mot/clear_mot.hpp"
#include "ucon/mot/runtime_frames.hpp"

namespace ucon {
namespace mot {

struct LogEvalOptions : RuntimeEvalOptions {
  bool allow_truncated = false;  ///< evaluate what was read before a truncated/corrupt tail
  /// When set, PERCEPTION_OBJECTS come from this log instead (e.g. `ucon-replay --node
  /// perception`'s output for the log that holds the ground truth).
  std::string objects_log;
};

/// What the log held.
struct LogMatchStats {
  int64_t events = 0;                       ///< events read
  int64_t ground_truth_messages = 0;
  int64_t perception_messages = 0;
  int64_t frames_evaluated = 0;             ///< perception frames given to CLEAR-MOT
  int64_t frames_without_ground_truth = 0;  ///< no SIM_GROUND_TRUTH within max_time_gap_s
  int64_t invalid_frames = 0;               ///< valid == false: evaluated with no hypotheses
  int64_t undecodable_messages = 0;         ///< on the two channels, dropped
  bool truncated = false;                   ///< the log ended inside an event or held garbage
  std::string warning;                      ///< why `truncated` is set
};

/// Reads the log (and opt.objects_log) and evaluates it. Returns nullopt with `error` set when the file cannot be
/// opened, is not an LCM log, holds no perception or no ground-truth messages, or is
/// truncated/corrupt (unless opt.allow_truncated).
std::optional<ClearMotSummary> evaluateLog(const std::string& path, const LogEvalOptions& opt,
                                           LogMatchStats* stats, std::string* error);

}  // namespace mot
}  // namespace ucon
