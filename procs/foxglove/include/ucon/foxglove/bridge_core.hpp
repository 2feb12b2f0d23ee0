#pragma once
/// @file bridge_core.hpp
/// The live bridge's logic without sockets: which WebSocket channels exist (every ucon LCM
/// channel as JSON, plus the Foxglove views of convert.hpp, the same topics ucon-mcap
/// writes), and what one LCM message becomes on them. Work is done only for channels
/// somebody subscribed to, except the static map, which accumulates all along.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ucon/foxglove/convert.hpp"
#include "ucon/foxglove/message_time.hpp"
#include "ucon/foxglove/ws_protocol.hpp"

namespace ucon {
namespace foxglove {

/// One message for the subscribers of a channel.
struct BridgeOutput {
  uint32_t channel_id = 0;
  uint64_t timestamp_ns = 0;                    ///< message time [ns]
  std::shared_ptr<const std::string> payload;   ///< JSON
};

struct BridgeStats {
  int64_t lcm_messages = 0;   ///< LCM messages seen
  int64_t converted = 0;      ///< outputs produced
  int64_t unknown_type = 0;   ///< messages of no ucon type
  int64_t undecodable = 0;    ///< ucon messages whose bytes did not decode
  int64_t untimed = 0;        ///< messages sent at another time than their own utime
};

class BridgeCore {
 public:
  /// Registers the channels of every channel the runtime knows (ucon::channels::all()), so
  /// that a client can subscribe before traffic flows; channels seen later are added then.
  explicit BridgeCore(const ViewParams& view);

  /// Channels registered since the last call, in id order (to advertise).
  std::vector<WsChannel> takeNewChannels();
  const std::map<uint32_t, WsChannel>& channels() const { return channels_; }

  /// Handles one LCM message: appends an output per subscribed channel it feeds (`wanted`
  /// says which). Unknown types and undecodable bytes are counted and dropped.
  void onLcm(const std::string& channel, const void* data, std::size_t size,
             const std::function<bool(uint32_t)>& wanted, std::vector<BridgeOutput>* out);

  /// The static map as it is now, for a client that just subscribed to it (nothing before
  /// the first static points, or without a map channel).
  void currentMap(std::vector<BridgeOutput>* out);

  /// Message clock [ns]: the latest message time seen (0 before the first).
  uint64_t nowNs() const { return static_cast<uint64_t>(clock_.now()) * 1000u; }
  const BridgeStats& stats() const { return stats_; }
  const ConvertStats& convertStats() const { return converter_.stats(); }

 private:
  uint32_t channelFor(const std::string& topic, const std::string& schema_name, const std::string& schema);
  void registerChannel(const std::string& channel, const LcmTypeInfo& type);

  FoxgloveConverter converter_;
  MessageClock clock_;
  BridgeStats stats_;
  std::map<uint32_t, WsChannel> channels_;
  std::map<std::pair<std::string, std::string>, uint32_t> by_topic_;  ///< (topic, schema) -> id
  std::map<std::string, std::vector<uint32_t>> lcm_channels_;        ///< LCM channel -> [raw, views...]
  std::vector<uint32_t> new_channels_;
  uint32_t next_id_ = 1;
  std::vector<FoxgloveMessage> converted_;
};

}  // namespace foxglove
}  // namespace ucon
