#pragma once
/// @file node_runtime.hpp
/// The I/O side shared by every process's main.cpp: opening LCM with a clear error,
/// SIGINT/SIGTERM handling, typed subscriptions that count undecodable messages, the one loop
/// shape (handleTimeout + tick), and the one way status is published. run() drives a node
/// from its binding (ucon/runtime/binding.hpp). Node classes never see this.

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ucon/process_status_t.hpp"
#include "ucon/runtime/binding.hpp"
#include "ucon/runtime/tick_timer.hpp"
#include "ucon/status_report.hpp"

namespace ucon {
namespace runtime {

/// Installs SIGINT/SIGTERM handlers that set the exit flag (idempotent).
void installSignalHandlers();
/// True once SIGINT/SIGTERM arrived or requestExit() was called.
bool exitRequested();
/// Sets the exit flag (tests, fatal errors).
void requestExit();
/// Clears the exit flag (tests that run several loops in one process).
void resetExitFlag();

/// Wall clock [us] — for latency and status timestamps only, never for node logic.
int64_t wallUtime();

/// Prints "[name] level: message" to stderr with the wall-clock time.
void logLine(const std::string& name, const char* level, const std::string& message);

/// How NodeRuntime::run drives a node, beyond its binding.
struct RunOptions {
  /// TickRule::kPeriodic: tick on message time only, before each message, as a replay does
  /// (instead of on a wall-clock timer that keeps ticking when messages stop).
  bool message_clock = false;
  /// Process-level work once per loop turn, after the tick (e.g. a line printed every second).
  std::function<void()> after_tick;
};

/// LCM connection, subscriptions and the loop of one process.
class NodeRuntime {
 public:
  /// Opens LCM at `url` (empty = LCM_DEFAULT_URL or the runtime default). Returns nullptr and
  /// fills `error` if the URL is malformed or the provider cannot start.
  static std::unique_ptr<NodeRuntime> open(const std::string& process_name, const std::string& url,
                                           std::string* error);

  NodeRuntime(const NodeRuntime&) = delete;
  NodeRuntime& operator=(const NodeRuntime&) = delete;
  ~NodeRuntime();

  lcm::LCM& lcm() { return *lcm_; }
  const std::string& url() const { return url_; }

  /// Drives `node` from its binding: subscribes its inputs, runs the one loop with its tick
  /// rule, publishes its status. Returns 0 on a clean exit (signal, requestExit(), or the
  /// binding's done()), 1 if LCM failed while running.
  template <class Node>
  int run(const NodeBinding<Node>& binding, Node& node, const RunOptions& options = {});

  /// What a node publishes: each message goes out on LCM at once ("publish_errors" counted);
  /// log lines go to logLine. Divert an output here (Outbox::divert) before run().
  Outbox& outbox() { return outbox_; }

  /// Subscribes `handler` to `channel` (a regex). Messages that fail to decode are counted as
  /// "decode_errors" on the status and dropped. The subscription queues up to `queue_capacity`
  /// messages while the loop is busy (LCM's default of 30 drops bursts silently).
  template <class Msg>
  void subscribe(const std::string& channel,
                 std::function<void(const Msg&, const std::string& channel)> handler,
                 int queue_capacity = kDefaultQueueCapacity);

  /// Subscription queue length used unless a subscriber asks otherwise.
  static constexpr int kDefaultQueueCapacity = 1000;

  /// Publishes `msg` on `channel`; counts "publish_errors" on failure.
  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    if (lcm_->publish(channel, &msg) != 0) count("publish_errors");
  }

  /// The process's status, the one way every process publishes it: every `period_s` of wall
  /// time (status is for people) the loop takes `report()` (the report the node owns, brought
  /// up to date), sets the runtime's counters in it (decode_errors, publish_errors, and those
  /// of addStatus), and publishes it on `channel` stamped with `clock()` (message time).
  void setStatus(const std::string& channel, double period_s, std::function<StatusReport&()> report,
                 std::function<int64_t()> clock);
  /// Adds process-level entries to every status message (e.g. a motor backend's counters).
  void addStatus(std::function<void(StatusReport&)> fn) { status_extras_.push_back(std::move(fn)); }

  /// The runtime's own counters ("decode_errors", "publish_errors"); 0 if never counted.
  int64_t counter(const std::string& name) const;
  void count(const std::string& name, int64_t n = 1) { counters_[name] += n; }

  /// The loop: `while (!exitRequested()) { handleTimeout(timeout_ms); tick(); status }`.
  /// Every kTrimPeriodS of wall time it also hands the heap's free pages back to the system
  /// (malloc_trim): a burst of large messages or a container that grew would otherwise keep
  /// its high-water mark resident for the rest of a long run. It changes no output.
  /// `tick` may be empty. Returns 0 on a clean exit, 1 if LCM failed while running.
  int spin(int timeout_ms, const std::function<void()>& tick);
  static constexpr double kTrimPeriodS = 10.0;
  /// The period of that hand-back [s] (tests); 0 turns it off.
  void setTrimPeriod(double seconds) { trim_period_s_ = seconds; }

  /// Handles at most one message (or times out); for tests and custom loops. Returns
  /// handleTimeout's result.
  int handleOnce(int timeout_ms);

  /// Publishes the status message now (nothing without setStatus).
  void publishStatus();

 private:
  NodeRuntime(std::string name, std::string url, std::unique_ptr<lcm::LCM> lcm);

  /// spin() with a wait chosen before each turn.
  int loop(const std::function<int()>& timeout_ms, const std::function<void()>& tick);
  /// Subscribes `fn` to the raw bytes of `channel`.
  void subscribeRaw(const std::string& channel, std::function<void(const uint8_t*, std::size_t)> fn,
                    int queue_capacity = kDefaultQueueCapacity);

  struct RawHandler;

  struct HandlerBase {
    virtual ~HandlerBase() = default;
  };
  template <class Msg>
  struct Handler : HandlerBase {
    NodeRuntime* owner;
    std::function<void(const Msg&, const std::string&)> fn;
    void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      Msg msg;
      const int n = msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size));
      if (n < 0 || static_cast<uint32_t>(n) != rbuf->data_size) {
        owner->count("decode_errors");
        return;
      }
      fn(msg, channel);
    }
  };

  std::string name_;
  std::string url_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::vector<std::unique_ptr<HandlerBase>> handlers_;
  std::map<std::string, int64_t> counters_;
  Outbox outbox_;
  std::string status_channel_;
  double status_period_s_ = 1.0;
  std::function<StatusReport&()> status_report_;
  std::function<int64_t()> status_clock_;
  std::vector<std::function<void(StatusReport&)>> status_extras_;
  std::chrono::steady_clock::time_point next_status_;
  std::chrono::steady_clock::time_point next_trim_;
  double trim_period_s_ = kTrimPeriodS;
};

struct NodeRuntime::RawHandler : HandlerBase {
  std::function<void(const uint8_t*, std::size_t)> fn;
  void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    fn(static_cast<const uint8_t*>(rbuf->data), rbuf->data_size);
  }
};

template <class Msg>
void NodeRuntime::subscribe(const std::string& channel,
                            std::function<void(const Msg&, const std::string&)> handler,
                            int queue_capacity) {
  auto h = std::make_unique<Handler<Msg>>();
  h->owner = this;
  h->fn = std::move(handler);
  lcm::Subscription* sub = lcm_->subscribe(channel, &Handler<Msg>::onRaw, h.get());
  if (sub) sub->setQueueCapacity(queue_capacity);
  handlers_.push_back(std::move(h));
}

template <class Node>
int NodeRuntime::run(const NodeBinding<Node>& binding, Node& node, const RunOptions& options) {
  // What the subscriptions and the status use lives as long as this runtime.
  struct State : HandlerBase {
    NodeBinding<Node> b;
    Node* node = nullptr;
    std::unique_ptr<TickTimer> timer;
    bool message_clock = false;
    std::function<void(int64_t)> before;
  };
  auto owned = std::make_unique<State>();
  State* s = owned.get();
  handlers_.push_back(std::move(owned));
  s->b = binding;
  s->node = &node;
  const TickRule rule = s->b.tick_rule;
  if (rule.kind == TickRule::Kind::kPeriodic) {
    s->timer = std::make_unique<TickTimer>(
        options.message_clock ? TickTimer::Mode::kMessage : TickTimer::Mode::kLive, rule.rate_hz);
    s->message_clock = options.message_clock;
  }
  // Message clock: the ticks due before a message run before its handler (as in a replay).
  if (s->message_clock) {
    s->before = [this, s](int64_t utime) {
      s->timer->observe(utime, wallUtime());
      for (int64_t t : s->timer->due(wallUtime())) s->b.tick(*s->node, t, outbox_);
    };
  }
  for (const auto& in : s->b.inputs) {
    subscribeRaw(in.channel, [this, s, feed = in.feed](const uint8_t* data, std::size_t size) {
      const auto utime = feed(*s->node, data, size, outbox_, s->before);
      if (!utime) {
        count("decode_errors");
        return;
      }
      // Live clock: the timer is anchored on the message's time and its arrival (wall) time.
      if (s->timer && !s->message_clock) s->timer->observe(*utime, wallUtime());
    });
  }
  if (!s->b.status_channel.empty() && s->b.status) {
    setStatus(
        s->b.status_channel, s->b.status_period_s,
        [s]() -> StatusReport& {
          StatusReport& r = s->b.status(*s->node);
          if (s->timer) r.setCounter("ticks_skipped", s->timer->skippedTicks());
          return r;
        },
        [s] { return s->b.clock(*s->node); });
  }
  const auto timeout = [s, rule]() -> int {
    if (!s->timer || s->message_clock || s->timer->nextWallDeadline() <= 0) return rule.wait_ms;
    const int64_t wait_us = s->timer->nextWallDeadline() - wallUtime();
    return static_cast<int>(std::clamp<int64_t>((wait_us + 999) / 1000, 0, rule.wait_ms));
  };
  return loop(timeout, [this, s, rule, &options] {
    if (rule.kind == TickRule::Kind::kAfterInput) {
      s->b.tick(*s->node, s->b.clock(*s->node), outbox_);
    } else if (s->timer) {
      for (int64_t t : s->timer->due(wallUtime())) s->b.tick(*s->node, t, outbox_);
    }
    if (s->b.done && s->b.done(*s->node)) requestExit();
    if (options.after_tick) options.after_tick();
  });
}

}  // namespace runtime
}  // namespace ucon
