#pragma once
/// @file record_to_log.hpp
/// The file side of the in-process recorder: reads the configs and the scenario, builds the
/// nodes, runs recordSimulatedRun() and writes the LCM log (event timestamp = message utime).
/// ucon-sim-record, the replay tests and scripts/regen-golden.sh all record through this, so
/// the same spec gives the same bytes everywhere.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ucon/replay/sim_recorder.hpp"

namespace ucon {
namespace replay {

struct RecordingSpec {
  std::string scenario = "crossing";  ///< pedestrians | crossing | bench:<N_d>:<seed> | path.yaml
  double duration_s = 4.0;            ///< simulated seconds
  long long seed = -1;                ///< >= 0 overrides the scenario seed
  /// Nodes in the loop (NodeAdapter names). Without "planner", a scripted plan drives the base.
  std::vector<std::string> nodes;
  std::string config_dir;             ///< simulator.yaml, lidar_driver.yaml, <node>.yaml
  std::string scenario_dir;           ///< builtin scenarios
};

/// Records `spec` into `out_path`. False and `error` on a bad config, scenario or node, or
/// when the file cannot be written.
bool recordToLog(const RecordingSpec& spec, const std::string& out_path, RecordSummary* summary,
                 std::string* error);

/// Per channel: event count and FNV-1a 64 hash of (channel, timestamp, bytes) of every event,
/// in log order. Compact evidence of what a log holds (the golden manifest keeps the
/// recording's digest so a changed input is told apart from a changed node).
struct ChannelDigest {
  int64_t events = 0;
  uint64_t hash = 1469598103934665603ull;
};
/// nullopt and `error` (with the byte offset) when the log is damaged.
std::optional<std::map<std::string, ChannelDigest>> digestLog(const std::string& path, std::string* error);

/// "a,b" -> {"a", "b"}; "all" -> availableNodes(); "none" or "" -> {}.
std::vector<std::string> parseNodeList(const std::string& list);

}  // namespace replay
}  // namespace ucon
