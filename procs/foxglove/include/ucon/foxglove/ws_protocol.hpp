#pragma once
/// @file ws_protocol.hpp
/// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1) as the bridge speaks
/// it, without sockets: the server's JSON messages (serverInfo, advertise, status), its binary
/// frames (message data, time), the parsing of what a client sends, one client's
/// subscriptions, and the bounded send queue that drops the oldest message.
///
/// The bridge is read-only: it announces no capability but "time", and it answers every
/// client publication, parameter, service, connection-graph or asset request with an error
/// status instead of acting on it.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ucon {
namespace foxglove {

/// The only subprotocol the bridge accepts.
inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

/// True when a Sec-WebSocket-Protocol header value (a comma-separated list) offers kSubprotocol.
bool offersSubprotocol(const std::string& header_value);

/// One channel the server advertises.
struct WsChannel {
  uint32_t id = 0;
  std::string topic;
  std::string encoding = "json";
  std::string schema_name;
  std::string schema;                         ///< jsonschema text
  std::string schema_encoding = "jsonschema";
};

/// Status levels of the protocol.
enum class StatusLevel : int { kInfo = 0, kWarning = 1, kError = 2 };

std::string serverInfoJson(const std::string& name, const std::string& instance_id);
std::string advertiseJson(const std::vector<WsChannel>& channels);
std::string statusJson(StatusLevel level, const std::string& message);

/// Binary Message Data header: opcode 0x01, subscription id (uint32 LE), timestamp [ns]
/// (uint64 LE); the payload follows it in the same frame.
std::string messageDataHeader(uint32_t subscription_id, uint64_t timestamp_ns);
/// Binary Time message: opcode 0x02, timestamp [ns] (uint64 LE).
std::string timeMessage(uint64_t timestamp_ns);

/// What a client's text message asks for.
struct ClientRequest {
  enum class Kind { kSubscribe, kUnsubscribe, kRefused, kInvalid };
  Kind kind = Kind::kInvalid;
  std::string op;                                          ///< the message's "op"
  std::vector<std::pair<uint32_t, uint32_t>> subscribe;    ///< (subscription id, channel id)
  std::vector<uint32_t> unsubscribe;                       ///< subscription ids
  std::string error;                                       ///< why kRefused / kInvalid, for a status message
};

/// Parses a client text message. Anything but subscribe / unsubscribe is refused (the bridge
/// is read-only); malformed JSON or fields are invalid. Never throws.
ClientRequest parseClientText(const std::string& text);

/// The error a client binary message gets (client message data, service calls: refused).
std::string refuseClientBinary(const uint8_t* data, std::size_t size);

/// One client's subscriptions: subscription id <-> channel id.
class ClientSubscriptions {
 public:
  /// Adds the subscriptions whose channel exists and whose id and channel are not in use;
  /// returns one error text per rejected entry. `added` receives the accepted channel ids.
  std::vector<std::string> subscribe(const std::vector<std::pair<uint32_t, uint32_t>>& requests,
                                     const std::map<uint32_t, WsChannel>& channels,
                                     std::vector<uint32_t>* added);
  /// Removes subscriptions; returns an error text per unknown id. `removed` receives their channel ids.
  std::vector<std::string> unsubscribe(const std::vector<uint32_t>& ids, std::vector<uint32_t>* removed);
  /// The client's subscription id for a channel.
  std::optional<uint32_t> subscriptionFor(uint32_t channel_id) const;
  /// Every subscribed channel id.
  std::vector<uint32_t> channels() const;

 private:
  std::map<uint32_t, uint32_t> by_subscription_;  ///< subscription id -> channel id
  std::map<uint32_t, uint32_t> by_channel_;       ///< channel id -> subscription id
};

/// One frame to send: text (JSON) or binary (header + shared payload, so that one converted
/// message serves every client without copies).
struct OutFrame {
  bool text = false;
  std::string head;                              ///< text: the JSON; binary: the header bytes
  std::shared_ptr<const std::string> payload;    ///< binary payload (may be null)
  std::size_t size() const { return head.size() + (payload ? payload->size() : 0); }
};

/// Bounded queue of data frames: when a push would exceed max_frames or max_bytes, the
/// oldest frames are dropped (and counted) first, so that a slow client gets the newest
/// data late rather than old data later, and never holds the server back.
class DropOldestQueue {
 public:
  DropOldestQueue(std::size_t max_frames, std::size_t max_bytes) : max_frames_(max_frames), max_bytes_(max_bytes) {}
  /// Appends `f`; returns how many frames were dropped to make room (a frame larger than
  /// max_bytes on its own is still kept, alone).
  std::size_t push(OutFrame f);
  /// Removes and returns the oldest frame; nullopt when empty.
  std::optional<OutFrame> pop();
  bool empty() const { return frames_.empty(); }
  std::size_t size() const { return frames_.size(); }
  std::size_t bytes() const { return bytes_; }
  uint64_t dropped() const { return dropped_; }

 private:
  std::size_t max_frames_, max_bytes_;
  std::deque<OutFrame> frames_;
  std::size_t bytes_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace foxglove
}  // namespace ucon
