#pragma once
/// @file replay_runner.hpp
/// Lock-step replay of an LCM log through one node (NodeAdapter), writing the node's outputs
/// to a new log with each message's utime as the event timestamp, so that two replays of the
/// same log give byte-identical files. The input is read strictly (ucon::runtime::LogReader):
/// a truncated or corrupt event stops the replay with an error naming its byte offset.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ucon/replay/node_adapter.hpp"

namespace ucon {
namespace replay {

/// Counts of one replay.
struct ReplaySummary {
  int64_t events = 0;         ///< events read from the input log
  int64_t handled = 0;        ///< given to the node
  int64_t ignored = 0;        ///< not an input of the node
  int64_t decode_errors = 0;  ///< input channel, undecodable bytes
  int64_t outputs = 0;        ///< messages written
  std::map<std::string, int64_t> outputs_per_channel;
};

struct ReplayResult {
  bool ok = false;
  std::string error;  ///< why not ok: "run.lcm: truncated event (...) at byte offset N"
  ReplaySummary summary;
};

/// Replays `in_path` through `node` into `out_path` (created or overwritten). On an input
/// error the partial output file is removed, so it is never mistaken for a full replay.
ReplayResult replayLog(NodeAdapter& node, const std::string& in_path, const std::string& out_path);

/// The config text of `node` recorded by the logger in the log's first LOG_METADATA event
/// (key "config/<node>.yaml"); nullopt and `error` when the log has none.
std::optional<std::string> configFromLog(const std::string& log_path, const std::string& node,
                                         std::string* error);

/// An ECMAScript regex matching exactly these channel names ("^(A|B)$").
std::string exactChannelRegex(const std::vector<std::string>& channels);

}  // namespace replay
}  // namespace ucon
