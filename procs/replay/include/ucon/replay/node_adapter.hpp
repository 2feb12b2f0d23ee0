#pragma once
/// @file node_adapter.hpp
/// How a node is driven in lock step from recorded messages, without LCM: an adapter says
/// which channels the node consumes, hands each message to the right handler, runs the ticks
/// the live process would run around it, and returns what the node asked to publish (encoded,
/// with the message's utime). The replay tool, the in-process recorder and the tests all drive
/// nodes through this interface, so they feed a node exactly the same way.
///
/// A node's adapter is a BoundAdapter (bound_adapter.hpp) made from the node's binding, the
/// same declaration of channels, handlers and tick rule that its process runs on. Outputs
/// that carry wall-clock data (the <NODE>_STATUS process status) are not produced: a replay
/// writes only what the node computes from its inputs.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ucon {
namespace replay {

/// One message a node asked to publish.
struct OutputMessage {
  std::string channel;
  int64_t utime = 0;          ///< the message's own utime [us]
  std::vector<uint8_t> data;  ///< LCM encoding
};

/// What happened to one fed event.
enum class FeedResult {
  kHandled,      ///< an input channel of the node; decoded and handed over
  kIgnored,      ///< not an input of this node
  kDecodeError,  ///< an input channel, but the bytes are not a valid message: counted, dropped
};
const char* toString(FeedResult r);

class NodeAdapter {
 public:
  virtual ~NodeAdapter() = default;

  /// Node name as given to --node ("base_controller", ...).
  virtual std::string name() const = 0;
  /// Channels the node consumes (exact names).
  virtual std::vector<std::string> inputChannels() const = 0;
  /// Channels it publishes through this adapter.
  virtual std::vector<std::string> outputChannels() const = 0;

  /// Feeds one recorded event. Appends everything the node published because of it (ticks
  /// due before it, then the handler's output, then ticks after it), in order.
  virtual FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                          std::vector<OutputMessage>* out) = 0;

  /// Node counters for a summary (name, value), in a fixed order.
  virtual std::vector<std::pair<std::string, int64_t>> counters() const = 0;
  /// CPU seconds used so far by threads the node runs besides the one that calls feed()
  /// (a helper thread of the planner's map insertion); 0 for most nodes. Measurement only.
  virtual double helperCpuSeconds() const { return 0.0; }

  /// True if `channel` is one of inputChannels().
  bool consumes(const std::string& channel) const;
};

/// Nodes this build can replay, in a fixed order (perception and planner only when their
/// node libraries were built).
std::vector<std::string> availableNodes();

/// True if `node` is a known node name, built or not.
bool isKnownNode(const std::string& node);

/// Makes the adapter of `node` with the config given as YAML text (`source` names it in
/// errors). nullptr and `error` for an unknown or unbuilt node or a bad config.
std::unique_ptr<NodeAdapter> makeAdapter(const std::string& node, const std::string& config_yaml,
                                         const std::string& source, std::string* error);

/// Encodes an LCM message into an OutputMessage.
template <class Msg>
OutputMessage encodeOutput(const std::string& channel, const Msg& msg) {
  OutputMessage o;
  o.channel = channel;
  o.utime = msg.utime;
  o.data.resize(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(o.data.data(), 0, static_cast<int>(o.data.size()));
  return o;
}

/// Decodes exactly `size` bytes into `msg`; false on any mismatch.
template <class Msg>
bool decodeExact(const uint8_t* data, std::size_t size, Msg* msg) {
  if (data == nullptr && size > 0) return false;
  return msg->decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
}

}  // namespace replay
}  // namespace ucon
