#pragma once
/// @file binding.hpp
/// A node's wiring, declared once: the channels it reads (LCM type and handler of each), the
/// channels it writes, when it ticks and where its status goes. The live process
/// (NodeRuntime::run, over LCM) and the lock-step replay (replay::BoundAdapter, no LCM) both
/// drive the node from this one declaration, so the two cannot wire it differently.
///
/// Pure: nothing here opens a socket or reads a clock. A node library declares its binding in
/// `ucon/<node>/binding.hpp`; its main and its replay adapter include it.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ucon/status_report.hpp"

namespace ucon {
namespace runtime {

/// A channel a node publishes on, with its message type: declared once in the binding and
/// used by its handlers, so a message cannot go out on a channel under another type.
template <class Msg>
struct Output {
  const char* channel;
};

/// Where a node's handlers put what they publish, and their log lines. The live process sends
/// each message at once (LCM); the lock-step replay keeps them, in order.
class Outbox {
 public:
  /// Receives one encoded message: channel, the message's utime [us], its LCM bytes.
  using Sink = std::function<void(const std::string& channel, int64_t utime, const uint8_t* data,
                                  std::size_t size)>;
  /// Receives a log line: level ("info", "warn", "error") and text.
  using LogSink = std::function<void(const char* level, const std::string& text)>;

  explicit Outbox(Sink sink, LogSink log = {}) : sink_(std::move(sink)), log_(std::move(log)) {}

  /// Publishes `msg` on `out` (or hands it to the function diverted there).
  template <class Msg>
  void publish(const Output<Msg>& out, const Msg& msg) {
    if (!diverted_.empty()) {
      const auto it = diverted_.find(out.channel);
      if (it != diverted_.end() && it->second.hash == Msg::getHash()) {
        it->second.fn(&msg);
        return;
      }
    }
    buffer_.resize(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    sink_(out.channel, msg.utime, buffer_.data(), buffer_.size());
  }

  /// Sends what is published on `out` to `fn` instead (e.g. wheel commands to a motor board).
  /// `fn(const Msg&)`.
  template <class Msg, class Fn>
  void divert(const Output<Msg>& out, Fn fn) {
    diverted_[out.channel] = Diverted{Msg::getHash(), [fn = std::move(fn)](const void* m) {
                                        fn(*static_cast<const Msg*>(m));
                                      }};
  }

  /// A log line of the node's process (dropped in replay).
  void log(const char* level, const std::string& text) {
    if (log_) log_(level, text);
  }

 private:
  struct Diverted {
    int64_t hash = 0;
    std::function<void(const void*)> fn;
  };
  Sink sink_;
  LogSink log_;
  std::map<std::string, Diverted> diverted_;
  std::vector<uint8_t> buffer_;
};

/// When a node's tick runs.
struct TickRule {
  enum class Kind {
    kNone,        ///< never: the handlers do everything
    kAfterInput,  ///< tick(now) after every input, now = the node's clock; live, also after a
                  ///< wait of `wait_ms` without input (now unchanged)
    kPeriodic,    ///< tick(t) at every multiple t of 1/rate_hz in message time (see TickTimer)
  };
  Kind kind = Kind::kNone;
  int wait_ms = 100;     ///< live: longest wait for a message [ms]
  double rate_hz = 0.0;  ///< kPeriodic: tick rate [Hz] (> 0)

  static TickRule none(int wait_ms) { return {Kind::kNone, wait_ms, 0.0}; }
  static TickRule afterInput(int wait_ms) { return {Kind::kAfterInput, wait_ms, 0.0}; }
  static TickRule periodic(double rate_hz) { return {Kind::kPeriodic, 100, rate_hz}; }
};

/// One input of a node: a channel, its LCM type and the handler the message goes to.
template <class Node>
struct Input {
  std::string channel;
  std::string type;  ///< LCM type name ("ucon.robot_pose_t")
  /// Decodes exactly `size` bytes. If they are one message: calls `before(utime)`, hands the
  /// message to the node's handler and returns the message's utime [us]; else nullopt and
  /// nothing is called.
  std::function<std::optional<int64_t>(Node&, const uint8_t* data, std::size_t size, Outbox&,
                                       const std::function<void(int64_t)>& before)>
      feed;
};

/// Declares an input: `handler(Node&, const Msg&, Outbox&)` gets each message on `channel`.
template <class Msg, class Node, class Handler>
Input<Node> input(const char* channel, Handler handler) {
  Input<Node> in;
  in.channel = channel;
  in.type = std::string("ucon.") + Msg::getTypeName();
  in.feed = [handler = std::move(handler)](Node& node, const uint8_t* data, std::size_t size, Outbox& out,
                                           const std::function<void(int64_t)>& before)
      -> std::optional<int64_t> {
    if (data == nullptr && size > 0) return std::nullopt;
    Msg msg;
    if (msg.decode(data, 0, static_cast<int>(size)) != static_cast<int>(size)) return std::nullopt;
    if (before) before(msg.utime);
    handler(node, msg, out);
    return msg.utime;
  };
  return in;
}

/// Everything a harness needs to run `Node` (the node class, or a small struct holding it with
/// what its process keeps beside it, such as its status report).
template <class Node>
struct NodeBinding {
  std::string name;                 ///< process name: status name, `ucon-replay --node`
  std::vector<Input<Node>> inputs;  ///< channels read, in no particular order
  std::vector<std::string> outputs; ///< channels published (what a replay writes and compares)
  TickRule tick_rule;
  /// The tick (kAfterInput: `now` is clock(node); kPeriodic: the grid time). Empty for kNone.
  std::function<void(Node&, int64_t now, Outbox&)> tick;
  /// The node's "now": the newest input utime it has seen [us].
  std::function<int64_t(const Node&)> clock;
  /// Status: channel (empty = none), period [s, wall time: status is for people], and the
  /// node's own report brought up to date. The runtime adds its counters (decode_errors,
  /// publish_errors, ticks_skipped) and publishes it, stamped with clock(node).
  std::string status_channel;
  double status_period_s = 1.0;
  std::function<StatusReport&(Node&)> status;
  /// Optional: true once the node has finished (the process then exits).
  std::function<bool(const Node&)> done;

  std::vector<std::string> inputChannels() const {
    std::vector<std::string> c;
    for (const auto& in : inputs) c.push_back(in.channel);
    return c;
  }
  const Input<Node>* findInput(const std::string& channel) const {
    for (const auto& in : inputs)
      if (in.channel == channel) return &in;
    return nullptr;
  }
};

}  // namespace runtime
}  // namespace ucon
