#pragma once
/// @file bridge_server.hpp
/// The WebSocket side of ucon-foxglove-bridge (Boost.Beast on one I/O thread): accepts clients
/// that ask for subprotocol foxglove.websocket.v1, sends them serverInfo and the channels,
/// keeps their subscriptions, and sends each subscribed message through the client's own
/// bounded queue (drop-oldest). publish() never blocks on a client: a slow or stalled client
/// loses its oldest messages, the LCM side goes on. Read-only: client publications,
/// parameters and services get an error status.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ucon/foxglove/bridge_core.hpp"
#include "ucon/foxglove/ws_protocol.hpp"

namespace ucon {
namespace foxglove {

class BridgeServer {
 public:
  struct Options {
    std::string bind = "127.0.0.1";   ///< address to listen on
    uint16_t port = 8765;             ///< TCP port (0: any free port)
    std::size_t queue_messages = 256; ///< per client: most messages waiting to be sent
    std::size_t queue_bytes = 16u << 20;  ///< per client: most bytes waiting to be sent
    int max_clients = 16;             ///< further connections are refused
    std::string name = "ucon-foxglove-bridge";
  };

  struct Stats {
    int clients = 0;            ///< connected now
    uint64_t connections = 0;   ///< accepted WebSocket connections since start
    uint64_t rejected = 0;      ///< connections refused (no subprotocol, too many clients, not WebSocket)
    uint64_t frames_sent = 0;
    uint64_t bytes_sent = 0;
    uint64_t dropped = 0;       ///< messages dropped from full client queues
    uint64_t refused_requests = 0;  ///< client publications, parameter or service requests refused
  };

  /// Listens and starts the I/O thread; nullptr and *error when the address cannot be used.
  static std::unique_ptr<BridgeServer> start(const Options& options, const std::vector<WsChannel>& channels,
                                             std::string* error);
  ~BridgeServer();
  BridgeServer(const BridgeServer&) = delete;
  BridgeServer& operator=(const BridgeServer&) = delete;

  /// The port actually listened on.
  uint16_t port() const;
  /// Adds channels and advertises them to every client.
  void advertise(const std::vector<WsChannel>& channels);
  /// True when some client subscribed to the channel.
  bool wanted(uint32_t channel_id) const;
  /// Queues each output for the clients subscribed to its channel. Never blocks on a client.
  void publish(const std::vector<BridgeOutput>& outputs);
  /// Sends a Time message to every client (through its queue: a slow client may lose it).
  void broadcastTime(uint64_t timestamp_ns);
  /// Channels that got a new subscriber since the last call.
  std::vector<uint32_t> takeNewSubscriptions();
  Stats stats() const;
  /// Closes every client (going away) and the listener, and joins the I/O thread (at most
  /// about two seconds for clients that do not answer the close).
  void stop();

  class Impl;

 private:
  explicit BridgeServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace foxglove
}  // namespace ucon
