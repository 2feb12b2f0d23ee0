#pragma once
/// @file bound_adapter.hpp
/// A NodeAdapter made from a node's binding (ucon/runtime/binding.hpp): the inputs, outputs and
/// tick rule the live process uses, driven in lock step on message time. Tick rules:
///  - kAfterInput: tick(now) after every handled input, now = the node's clock;
///  - kPeriodic: every tick due on the period grid before a message runs first (TickTimer in
///    message mode), then the message's handler;
///  - kNone: the handlers only.
/// The status report is not replayed: it carries wall-clock data.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ucon/replay/node_adapter.hpp"
#include "ucon/runtime/binding.hpp"
#include "ucon/runtime/tick_timer.hpp"

namespace ucon {
namespace replay {

/// What a BoundAdapter fed and published, per channel.
struct FeedCounts {
  std::map<std::string, int64_t> in;   ///< handled inputs per channel
  std::map<std::string, int64_t> out;  ///< outputs per channel
  int64_t decode_errors = 0;
  int64_t inputs(const std::string& channel) const {
    const auto it = in.find(channel);
    return it == in.end() ? 0 : it->second;
  }
  int64_t outputs(const std::string& channel) const {
    const auto it = out.find(channel);
    return it == out.end() ? 0 : it->second;
  }
};

template <class Node>
class BoundAdapter : public NodeAdapter {
 public:
  /// The node's counters for a summary, from the node and what was fed.
  using Counters = std::function<std::vector<std::pair<std::string, int64_t>>(const Node&, const FeedCounts&)>;

  BoundAdapter(runtime::NodeBinding<Node> binding, std::unique_ptr<Node> node, Counters counters)
      : binding_(std::move(binding)),
        node_(std::move(node)),
        counters_(std::move(counters)),
        timer_(runtime::TickTimer::Mode::kMessage,
               binding_.tick_rule.kind == runtime::TickRule::Kind::kPeriodic ? binding_.tick_rule.rate_hz : 1.0),
        outbox_([this](const std::string& channel, int64_t utime, const uint8_t* data, std::size_t size) {
          OutputMessage o;
          o.channel = channel;
          o.utime = utime;
          o.data.assign(data, data + size);
          ++counts_.out[channel];
          out_->push_back(std::move(o));
        }) {}

  std::string name() const override { return binding_.name; }
  std::vector<std::string> inputChannels() const override { return binding_.inputChannels(); }
  std::vector<std::string> outputChannels() const override { return binding_.outputs; }

  FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                  std::vector<OutputMessage>* out) override {
    const runtime::Input<Node>* in = binding_.findInput(channel);
    if (in == nullptr) return FeedResult::kIgnored;
    out_ = out;
    const auto kind = binding_.tick_rule.kind;
    std::function<void(int64_t)> before;
    if (kind == runtime::TickRule::Kind::kPeriodic) {
      before = [this](int64_t utime) {
        timer_.observe(utime, 0);
        for (int64_t t : timer_.due(0)) binding_.tick(*node_, t, outbox_);
      };
    }
    if (!in->feed(*node_, data, size, outbox_, before)) {
      ++counts_.decode_errors;
      return FeedResult::kDecodeError;
    }
    ++counts_.in[channel];
    if (kind == runtime::TickRule::Kind::kAfterInput) binding_.tick(*node_, binding_.clock(*node_), outbox_);
    if (on_handled_) on_handled_(*node_, channel);
    return FeedResult::kHandled;
  }

  std::vector<std::pair<std::string, int64_t>> counters() const override { return counters_(*node_, counts_); }
  double helperCpuSeconds() const override { return helper_cpu_ ? helper_cpu_(*node_) : 0.0; }

  /// Measurement hooks: called after each handled input; CPU of the node's helper threads.
  void onHandled(std::function<void(const Node&, const std::string& channel)> fn) { on_handled_ = std::move(fn); }
  void helperCpu(std::function<double(const Node&)> fn) { helper_cpu_ = std::move(fn); }

  const Node& node() const { return *node_; }

 private:
  runtime::NodeBinding<Node> binding_;
  std::unique_ptr<Node> node_;
  Counters counters_;
  runtime::TickTimer timer_;
  runtime::Outbox outbox_;
  std::vector<OutputMessage>* out_ = nullptr;
  FeedCounts counts_;
  std::function<void(const Node&, const std::string&)> on_handled_;
  std::function<double(const Node&)> helper_cpu_;
};

}  // namespace replay
}  // namespace ucon
